// Tone-mapped frames (units counts8: a camera's 8-bit AGC video, e.g. V4L2 GREY/YUYV/UYVY) are
// never corrected as if they were linear counts: `bolo correct` (a recording or a live source)
// and `bolo run` refuse them before anything is written.

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

TEST_CASE("correct and run refuse tone-mapped (counts8) frames before writing anything", "[cli][correct][run]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  {
    rec::Recording linear(tmp / "rec");
    rec::RecordingInfo info = linear.info();
    info.units = rec::Units::counts8;
    info.bits = 8;
    rec::RecordingWriter writer(tmp / "agc", info);
    for (std::uint64_t i = 0; i < linear.frame_count(); ++i) {
      std::vector<std::uint16_t> frame = read_u16_frame(linear, i);
      for (std::uint16_t& p : frame) p = static_cast<std::uint16_t>(p >> 8);
      writer.append(frame, linear.rows()[i]);
    }
    writer.commit();
  }
  const std::string why =
      ": units counts8 (8-bit tone-mapped video, e.g. V4L2 GREY/YUYV/UYVY): the correction needs the sensor's "
      "linear counts; record the camera's Y16 (v4l2:/dev/videoN?format=Y16)";
  const std::string agc = (tmp / "agc").string();
  CHECK(contains(refused(correct_args(tmp, "agc", "out")), "bolo: error: " + agc + why));
  const std::vector<std::string> timing = {"--tau-h", "0.012", "--tau-c", "0.012"};
  CHECK(contains(refused(with({"run", "--device", "file:" + agc, "--sink", "recording:" + (tmp / "ran").string()},
                              timing)),
                 "file:" + agc + why));
  CHECK(entries(tmp.path()) == std::set<std::string>{"rec", "agc"});
  // The same frames in counts are corrected.
  REQUIRE(run_bolo(with(correct_args(tmp, "rec", "out"), {"--no-progress"})).code == 0);
}
