// bolo info: text and JSON on a recording made here, and facts known about the shared ones.

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

nlohmann::json info_json(const fs::path& dir) {
  const CliResult r = run_bolo({"info", dir.string(), "--json"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST_CASE("info: text summary of the small recording", "[cli][info]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  std::ostringstream out;
  REQUIRE(cli::run_info({tmp / "rec", false}, out) == 0);
  const std::string text = out.str();
  INFO(text);
  for (const char* expected :
       {"test sensor", "size            24 x 16, 14 bits, units counts, uint16 frames",
        "frames          12\n", "fps             10.00 declared, 10.00 measured (median interval 100.0 ms)",
        "ffc events      1 (before frame 6)",
        "gaps            1 (interval > 1.5 x median): frames 9->10 (300.0 ms)",
        "duplicates      1 (frames identical to their predecessor: 3)",
        "exposure_s      all frames, 0.008000 .. 0.009000 s", "readout_s       all frames, 0.004000 .. 0.007000 s",
        "fpa_temp_c      all frames, 30.00 .. 30.11 C", "housing_temp_c  absent",
        "files           scene.npy no, camera.json yes, poses.tum no"})
    CHECK(text.find(expected) != std::string::npos);
}

TEST_CASE("info --json: the same facts as JSON", "[cli][info]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec", [](std::uint64_t i) { return i < 8; });
  const nlohmann::json j = info_json(tmp / "rec");
  CHECK(j.at("width") == 24);
  CHECK(j.at("height") == 16);
  CHECK(j.at("bits") == 14);
  CHECK(j.at("units") == "counts");
  CHECK(j.at("dtype") == "uint16");
  CHECK(j.at("frames") == 12);
  CHECK(j.at("fps_declared").get<double>() == Approx(10.0));
  CHECK(j.at("fps_measured").get<double>() == Approx(10.0));
  CHECK(j.at("duration_s").get<double>() == Approx(1.3));
  CHECK(j.at("ffc_events") == nlohmann::json::array({6}));
  REQUIRE(j.at("gaps").size() == 1);
  CHECK(j.at("gaps")[0].at("previous") == 9);
  CHECK(j.at("gaps")[0].at("frame") == 10);
  CHECK(j.at("gaps")[0].at("interval_s").get<double>() == Approx(0.3));
  CHECK(j.at("duplicates") == nlohmann::json::array({3}));
  CHECK(j.at("columns").at("t_s").at("frames") == 12);
  CHECK(j.at("columns").at("exposure_s").at("frames") == 8);  // partial
  CHECK(j.at("columns").at("readout_s").at("frames") == 8);
  CHECK(j.at("columns").at("housing_temp_c").at("frames") == 0);
  CHECK(j.at("columns").at("fpa_temp_c").at("min").get<double>() == Approx(30.0));
  CHECK(j.at("files").at("camera.json") == true);
  CHECK(j.at("files").at("scene.npy") == false);
  CHECK(j.at("files").at("poses.tum") == false);
}

TEST_CASE("info on the shared recordings: FFC event, duplicates, empty timing columns", "[cli][info][shared]") {
  const fs::path ffc = shared_recording("lepton35-trailcam-ffc");
  if (ffc.empty()) return;
  {
    const nlohmann::json j = info_json(ffc);
    CHECK(j.at("frames") == 379);
    CHECK(j.at("units") == "centikelvin");
    CHECK(j.at("ffc_events") == nlohmann::json::array({309}));
    CHECK(j.at("columns").at("exposure_s").at("frames") == 0);
    CHECK(j.at("fps_measured").get<double>() == Approx(8.7).margin(0.2));
  }
  const fs::path telemetry = shared_recording("flirone-lepton-telemetry");
  const nlohmann::json j = info_json(telemetry);
  CHECK(j.at("duplicates") == nlohmann::json::array({1, 11}));
  CHECK(j.at("columns").at("housing_temp_c").at("frames") == 20);
}
