// The shared real recordings (the cases report SKIP when ../shared/data is absent): a static
// camera baseline, the shutter event of lepton35-trailcam-ffc found as ffc_step with and without
// its flag, with its real time stamps (a 1.8 s gap at the event) and with uniform ones.

#include <cstdio>
#include <fstream>
#include <sstream>

#include <catch2/catch.hpp>

#include "diagnose_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

// A copy of a recording whose frames.csv has every ffc flag cleared and, with `uniform_times`,
// t_s on the nominal period (frames.npy linked, not copied).
fs::path without_shutter_flags(const fs::path& source, const fs::path& out, bool uniform_times) {
  fs::create_directories(out);
  fs::create_symlink(source / "frames.npy", out / "frames.npy");
  fs::copy_file(source / "recording.json", out / "recording.json");
  const double fps = nlohmann::json::parse(read_text(source / "recording.json"))["fps"].get<double>();
  edit_frames_csv(source / "frames.csv", out / "frames.csv", [&](int row, std::vector<std::string>& cells) {
    if (uniform_times) {
      char t[32];
      std::snprintf(t, sizeof t, "%.6f", row / fps);
      cells[1] = t;
    }
    if (!cells[4].empty()) cells[4] = "0";
  });
  return out;
}

bool has_frame_near(const nlohmann::json& frames, int frame, int tolerance) {
  for (const auto& f : frames)
    if (std::abs(f.get<int>() - frame) <= tolerance) return true;
  return false;
}

}  // namespace

TEST_CASE("lepton35-trailcam-ffc: the shutter event is found at frame 309", "[diagnose][shared]") {
  const fs::path rec = shared_recording("lepton35-trailcam-ffc");
  if (rec.empty()) return;
  TempDir tmp;
  const nlohmann::json d = diagnose(rec, tmp / "d");
  CHECK(d["baseline"]["model"] == "static-background");
  CHECK(d["baseline"]["assumption"].get<std::string>().find("static camera") != std::string::npos);
  const nlohmann::json* f = finding(d, "ffc_step");
  REQUIRE(f);
  CHECK(has_frame_near((*f)["params"]["frames"], 309, 0));
}

// Issue 40: a real clip whose shutter event is not flagged. The frame mean steps at the event and
// then settles over ~20 frames to a level ~140 counts higher (the core's filter and re-settling);
// frames.csv's real time stamps have a 1.8 s gap there, the uniform copy none.
TEST_CASE("lepton35-trailcam-ffc without its flag: the shutter event is found within a frame",
          "[diagnose][shared][long]") {
  const fs::path source = shared_recording("lepton35-trailcam-ffc");
  if (source.empty()) return;
  TempDir tmp;
  for (bool uniform : {false, true}) {
    INFO((uniform ? "uniform time stamps" : "real time stamps"));
    const fs::path rec = without_shutter_flags(source, tmp / (uniform ? "uniform" : "real"), uniform);
    const nlohmann::json d = diagnose(rec, tmp / (uniform ? "uniform.d" : "real.d"));
    INFO(d["findings"].dump());
    const nlohmann::json* f = finding(d, "ffc_step");
    REQUIRE(f);
    CHECK((*f)["params"]["flagged"] == 0);
    CHECK(has_frame_near((*f)["params"]["frames"], 309, 1));
    // The settling after the event is modelled: held out, the step alone left a third of the
    // baseline's error (45.4 -> 15.3); with the settling under 0.3 of it.
    CHECK((*f)["params"].contains("settling_steps"));
    CHECK((*f)["heldout_rms_after"].get<double>() < 0.3 * (*f)["heldout_rms_before"].get<double>());
  }
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
