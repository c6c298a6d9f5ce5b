// Motion within the exposure modelled, not masked: on a recording written by the study's second,
// independent generator (scripts/study/independent_generator.py: its own scene and sensor, the
// input sampled at 6 sub-steps within each exposure, timing jittered), a null is diagnosed on
// (nearly) all its pixel-frames with no finding. It needs a Python with NumPy; without one the
// case skips with the reason.

#include <cstdlib>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "../test_skip.hpp"
#include "diagnose_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

// $BOLO_NUMPY_PYTHON, python3 or /usr/bin/python3: the first that imports numpy ("" if none).
std::string numpy_python() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("BOLO_NUMPY_PYTHON")) candidates.push_back(env);
  candidates.push_back("python3");
  candidates.push_back("/usr/bin/python3");
  for (const auto& py : candidates)
    if (std::system(("\"" + py + "\" -c 'import numpy' > /dev/null 2>&1").c_str()) == 0) return py;
  return "";
}

}  // namespace

TEST_CASE("blobs moving within the exposure (second generator): a null, diagnosed on its moving pixels",
          "[diagnose][null][timing][long]") {
  // Its blobs' sharp edges cross pixels within an exposure. With the edges masked (before: 13 %
  // of the pixel-frames here) what leaked past the masks was named rolling_readout.
  const std::string py = numpy_python();
  if (py.empty()) return skip("no Python with NumPy for scripts/study/independent_generator.py (set BOLO_NUMPY_PYTHON)");
  TempDir tmp;
  const fs::path rec = tmp / "gen2-pan";
  const std::string generator = std::string(BOLO_TESTS_DIR) + "/../scripts/study/independent_generator.py";
  const std::string command = "\"" + py + "\" \"" + generator + "\" \"" + rec.string() +
                              "\" --case null:pan_hot_entry --seed 1 --size 96x72 --frames 120 > /dev/null";
  REQUIRE(std::system(command.c_str()) == 0);
  const nlohmann::json d = diagnose(rec, tmp / "gen2-pan.d");
  INFO(d["baseline"].dump(1));
  INFO(d["unexplained"].dump(1));
  CHECK(d["findings"].empty());
  CHECK(d["baseline"]["params"]["moving_fraction"].get<double>() < 0.02);
  CHECK(d["baseline"]["params"]["exposure_motion"].get<double>() > 0.1);
  CHECK(unexplained_with(d, "where the simulated input changes") == 0);
  CHECK(d["baseline"]["heldout_rms"].get<double>() < 1.1 * d["noise_floor_rms"].get<double>());
}
