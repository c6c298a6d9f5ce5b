// bolo correct over a live source (hal::open_source): the real FLIR ONE transfer log and a
// synthetic one with faults, each against `bolo capture` followed by `bolo correct` of the
// recording; and the refusal of a spec no backend knows.

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "../hal/flirone_frames.hpp"
#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

const std::vector<std::string> kCorrection = {"--tau-h", "0.012", "--tau-c", "0.012", "--exposure", "0.01",
                                               "--readout", "0.1", "--no-progress"};

CliResult run_correct(const std::string& in, const fs::path& out, std::vector<std::string> more = {}) {
  std::vector<std::string> args = {"correct", in, out.string()};
  args.insert(args.end(), kCorrection.begin(), kCorrection.end());
  args.insert(args.end(), more.begin(), more.end());
  return run_bolo(args);
}

// `bolo correct SPEC` writes what `bolo capture --device SPEC` then `bolo correct REC` write:
// frames.npy and frames.csv byte for byte; returns the live run's stdout.
std::string same_as_capture_then_correct(const std::string& spec, const TempDir& tmp,
                                         std::vector<std::string> more = {}) {
  const CliResult captured = run_bolo({"capture", "--device", spec, "--out", (tmp / "rec").string(), "--no-progress"});
  INFO(captured.err);
  REQUIRE(captured.code == 0);
  const CliResult recorded = run_correct((tmp / "rec").string(), tmp / "from-rec", more);
  INFO(recorded.err);
  REQUIRE(recorded.code == 0);
  const CliResult live = run_correct(spec, tmp / "live", more);
  INFO(live.err);
  REQUIRE(live.code == 0);
  CHECK(read_text(tmp / "live" / "frames.npy") == read_text(tmp / "from-rec" / "frames.npy"));
  CHECK(read_text(tmp / "live" / "frames.csv") == read_text(tmp / "from-rec" / "frames.csv"));
  // The correction did something: the corrected frames are not the raw ones.
  CHECK(read_text(tmp / "live" / "frames.npy") != read_text(tmp / "rec" / "frames.npy"));
  const auto info = nlohmann::json::parse(read_text(tmp / "live" / "recording.json"));  // --float: f4 frames
  CHECK(info.at("correction").at("live") == true);
  CHECK(info.at("width") == 80);
  CHECK(fs::exists(tmp / "live" / "capture.json"));
  return live.out;
}

}  // namespace

TEST_CASE("correct: the real FLIR ONE transfer log, live, gives capture-then-correct's frames",
          "[cli][correct][real]") {
  const fs::path log = shared_folder("usb/flirone-pro", "1.txt");
  if (log.empty()) return;
  TempDir tmp;
  const std::string out = same_as_capture_then_correct("flirone-log:" + log.string(), tmp);
  CHECK(contains(out, "corrected flirone-log:" + log.string() + " -> "));
  CHECK(contains(out, "input         live source: 0 faulted frames skipped; device faults: timeouts 0"));
  CHECK(contains(out, "frames        20: "));
  CHECK(contains(out, "exposure      the source for 0 frames, --exposure for 20"));
  TempDir ref;
  CHECK(same_as_capture_then_correct("flirone-log:" + log.string(), ref, {"--float", "--bad-pixels"}) != "");
}

TEST_CASE("correct: a live source's faulted frames are skipped and counted", "[cli][correct]") {
  TempDir tmp;
  write_flirone_log(tmp / "log", 10, {5});
  const std::string spec = "flirone-log:" + (tmp / "log").string();
  const std::string out = same_as_capture_then_correct(spec, tmp);
  CHECK(contains(out, "input         live source: 1 faulted frames skipped; device faults: timeouts 0, short 0, corrupt 1"));
  CHECK(contains(out, "frames        9: "));
  CHECK(rec::Recording(tmp / "live").frame_count() == 9);
  // --frames bounds it; too many faults in a row give up with nothing written.
  REQUIRE(run_correct(spec, tmp / "three", {"--frames", "3"}).code == 0);
  CHECK(rec::Recording(tmp / "three").frame_count() == 3);
  write_flirone_log(tmp / "bad", 6, {0, 1, 2, 3, 4});
  CHECK(contains(refused(with({"correct", "flirone-log:" + (tmp / "bad").string(), (tmp / "gave-up").string()},
                              {"--tau-h", "0.012", "--tau-c", "0.012", "--exposure", "0.01", "--readout", "0.1",
                               "--max-faults", "3"})),
                 "/bad: gave up after 3 faults in a row, 0 frames corrected, nothing written (timeouts 0, short 0, corrupt 4"));
  CHECK_FALSE(fs::exists(tmp / "gave-up"));
}

TEST_CASE("correct: a live source without timing needs --exposure and --readout", "[cli][correct]") {
  TempDir tmp;
  write_flirone_log(tmp / "log", 3);
  const std::string spec = "flirone-log:" + (tmp / "log").string();
  CHECK(contains(refused({"correct", spec, (tmp / "out").string(), "--tau-h", "0.012", "--tau-c", "0.012"}),
                 spec + ": frame 0: the source gives no exposure time and no --exposure given"));
  CHECK_FALSE(fs::exists(tmp / "out"));
}

TEST_CASE("correct: a spec no backend knows is refused by name, nothing written", "[cli][correct]") {
  TempDir tmp;
  const std::string err = refused(with({"correct", "nosuch:thing", (tmp / "out").string()}, kCorrection));
  CHECK(contains(err, "nosuch:thing: unknown device (expected "));
  CHECK(contains(err, "flirone-log:DIR"));
  CHECK(contains(refused(with({"correct", "usb:boson", (tmp / "out").string()}, kCorrection)),
                 "usb:boson: unknown USB camera 'boson'"));
  CHECK(contains(refused(with({"correct", "v4l2:/dev/video0", (tmp / "out").string()}, kCorrection)),
                 "--frames: required for a live camera (v4l2:/dev/video0)"));
  CHECK(contains(refused(with({"correct", "flirone-log:" + (tmp / "none").string(), (tmp / "out").string()},
                              kCorrection)),
                 "flirone-log:" + (tmp / "none").string() + ": "));
  CHECK(entries(tmp.path()).empty());
}
