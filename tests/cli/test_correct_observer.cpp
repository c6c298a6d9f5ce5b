// The correction driver's observers: every frame reaches them once, in order, with the stats the
// command writes to --stats and counts in its summary; correct takes file:REC and refuses sources
// that are not recordings.

#include <catch2/catch.hpp>

#include <sstream>

#include "bolo/correct/correction_summary.hpp"
#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

class Collect final : public correct::FrameObserver {
 public:
  void on_begin(std::uint64_t frames) override { announced.push_back(frames); }
  void on_frame(const correct::FrameStats& s) override { frames.push_back(s); }
  std::vector<std::uint64_t> announced;
  std::vector<correct::FrameStats> frames;
};

std::vector<std::vector<std::string>> csv_rows(const fs::path& file) {
  std::istringstream text(read_text(file));
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(text, line);  // header
  while (std::getline(text, line)) {
    std::vector<std::string> cells;
    std::istringstream cells_text(line);
    for (std::string cell; std::getline(cells_text, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

correct::CorrectRequest request(const TempDir& tmp, bool float_output) {
  correct::CorrectRequest r;
  r.input = tmp / "rec";
  r.output = tmp / (float_output ? "float" : "fixed");
  r.tau_h_s = 0.012;
  r.tau_c_s = 0.010;
  r.float_output = float_output;
  r.stats = tmp / (float_output ? "float.csv" : "fixed.csv");
  return r;
}

}  // namespace

TEST_CASE("correct: the observer sees every frame with the stats of --stats and the summary", "[cli][correct]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  for (const bool float_output : {false, true}) {
    INFO("float " << float_output);
    const correct::CorrectRequest r = request(tmp, float_output);
    Collect seen;
    correct::SummaryTally tally;
    correct::FrameObserver* const observers[] = {&seen, &tally};
    const correct::CorrectResult result = correct::correct_recording(r, observers);
    CHECK(result.frames == SmallRecording::kFrames);
    CHECK(seen.announced == std::vector<std::uint64_t>{SmallRecording::kFrames});
    REQUIRE(seen.frames.size() == SmallRecording::kFrames);
    const auto rows = csv_rows(*r.stats);
    REQUIRE(rows.size() == SmallRecording::kFrames);
    std::uint64_t applied = 0;
    for (std::uint64_t i = 0; i < SmallRecording::kFrames; ++i) {
      const correct::FrameStats& s = seen.frames[i];
      INFO("frame " << i);
      CHECK(s.frame == i);
      CHECK((s.carry_over == fw::CarryOver::applied) == SmallRecording::carries(i));
      applied += s.carry_over == fw::CarryOver::applied;
      REQUIRE(rows[i].size() == 8);
      CHECK(rows[i][0] == std::to_string(i));
      CHECK(rows[i][1] == fw::to_string(s.carry_over));
      CHECK(rows[i][2] == fw::to_string(s.coefficient_status));
      CHECK(std::stod(rows[i][3]) == s.gain);
      CHECK(std::stod(rows[i][4]) == s.carry);
      CHECK(rows[i][5] == std::to_string(s.saturated_low));
      CHECK(rows[i][6] == std::to_string(s.saturated_high));
      CHECK(rows[i][7] == std::to_string(s.bad_pixels_replaced));
      CHECK_FALSE(s.exposure_from_flag);
    }
    std::ostringstream summary;
    correct::print_summary(summary, r, tally, result);
    CHECK(contains(summary.str(), "frames        " + std::to_string(SmallRecording::kFrames) + ": " +
                                      std::to_string(applied) + " corrected against the previous frame"));
    CHECK(contains(summary.str(), "frames.csv for " + std::to_string(SmallRecording::kFrames) + " frames, --exposure for 0"));
  }
}

TEST_CASE("correct: the input may be a source spec naming a recording", "[cli][correct]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const auto args = [&](const std::string& in, const std::string& out) {
    return std::vector<std::string>{"correct", in, (tmp / out).string(), "--tau-h", "0.012", "--tau-c", "0.012",
                                    "--no-progress"};
  };
  const std::string spec = "file:" + (tmp / "rec").string();
  const CliResult r = run_bolo(args(spec, "out"));
  CHECK(r.code == 0);
  CHECK(contains(r.out, "corrected " + spec + " -> "));
  CHECK(rec::Recording(tmp / "out").frame_count() == SmallRecording::kFrames);
  CHECK(contains(refused(args("v4l2:/dev/video0", "o2")), "--frames: required for a live camera (v4l2:/dev/video0)"));
  CHECK(contains(refused(args("usb:boson", "o2")), "usb:boson: unknown USB camera 'boson'"));
  CHECK_FALSE(fs::exists(tmp / "o2"));
}
