// Effects outside the catalogue, made by hand on simulated null recordings: no catalogue effect
// may claim them, and they must be reported as unexplained, with where they are.

#include <cmath>
#include <cstdint>

#include <catch2/catch.hpp>

#include "diagnose_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

// Adds amplitude * sin(2 pi (row / period + cycles_per_frame * n)) to every pixel: bands that
// drift through the image, as mains interference does.
void add_drifting_bands(const fs::path& rec, double amplitude, double period, double cycles_per_frame) {
  add_to_frames(rec, [&](std::uint64_t n, std::uint64_t y, std::uint64_t) {
    return amplitude * std::sin(2 * M_PI * (double(y) / period + cycles_per_frame * double(n)));
  });
}

}  // namespace

// An effect outside the catalogue: row bands of 1.5 noise sigma that drift through the image
// from frame to frame. It changes every frame difference, so it used to pass for noise (noise
// floor 2.0 -> 3.5, nothing reported); the noise floor must stay the pixel noise's, no catalogue
// effect may claim the bands, and they must be reported as unexplained, with where they are.
TEST_CASE("drifting row bands outside the catalogue are reported as unexplained, not named", "[diagnose][unexplained]") {
  TempDir tmp;
  const fs::path rec = simulate(tmp, "bands", {}, 31);
  add_drifting_bands(rec, 3.0, 15.0, 0.37);
  const nlohmann::json d = diagnose(rec, tmp / "bands.d");
  INFO(d.dump(1));
  CHECK(d["noise_floor_rms"].get<double>() == Approx(2.02).epsilon(0.04));
  CHECK(d["findings"].empty());
  CHECK(unexplained_with(d, "changes from frame to frame") >= 1);
  bool rows = false;
  for (const auto& u : d["unexplained"]) {
    const std::string summary = u["where"]["summary"].get<std::string>();
    if (summary.rfind("rows ", 0) == 0 && summary.find("changes from frame to frame") != std::string::npos) {
      rows = true;
      CHECK(u["rms"].get<double>() == Approx(3.0 / std::sqrt(2.0)).epsilon(0.3));
    }
  }
  CHECK(rows);
}
