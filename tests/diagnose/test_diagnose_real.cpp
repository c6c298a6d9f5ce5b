// The shared real recordings (the cases report SKIP when ../shared/data is absent): a static
// camera baseline, the flagged shutter event of lepton35-trailcam-ffc found as ffc_step.

#include <catch2/catch.hpp>

#include "diagnose_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

TEST_CASE("lepton35-trailcam-ffc: the shutter event is found at frame 309", "[diagnose][shared]") {
  const fs::path rec = shared_recording("lepton35-trailcam-ffc");
  if (rec.empty()) return;
  TempDir tmp;
  const nlohmann::json d = diagnose(rec, tmp / "d");
  CHECK(d["baseline"]["model"] == "static-background");
  CHECK(d["baseline"]["assumption"].get<std::string>().find("static camera") != std::string::npos);
  const nlohmann::json* f = finding(d, "ffc_step");
  REQUIRE(f);
  CHECK((*f)["params"]["frames"].dump().find("309") != std::string::npos);
}

TEST_CASE("flirone-lepton-telemetry: the core's repeated frames are found", "[diagnose][shared]") {
  const fs::path rec = shared_recording("flirone-lepton-telemetry");
  if (rec.empty()) return;
  TempDir tmp;
  const nlohmann::json d = diagnose(rec, tmp / "d");
  CHECK(d["noise_floor_rms"].get<double>() > 0);
  // The capture's notes: frames 1 and 11 carry the core frame counter of 0 and 10 (exported twice).
  INFO(d["findings"].dump());
  const nlohmann::json* f = finding(d, "frame_duplication");
  REQUIRE(f);
  CHECK((*f)["params"]["frames"] == nlohmann::json::array({1, 11}));
}
