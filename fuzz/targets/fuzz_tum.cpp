// TUM trajectories (poses.tum ground truth, trajectory.tum of `bolo odometry`): odo::read_tum on
// the input as a file. Properties: what is accepted has finite times that strictly increase and
// proper rotations (orthonormal, determinant +1, finite translation); tum_line writes each pose
// back as text that reads back to the same pose within the format's nine decimals, wherever
// consecutive times are far enough apart for nine decimals to keep them increasing.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/LU>  // determinant()

#include "bolo/odometry/tum.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace bolo;

void check_proper_rotation(const vo::Mat3& r) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) BOLO_FUZZ_CHECK(std::isfinite(r(i, j)));
  BOLO_FUZZ_CHECK(((r.transpose() * r) - vo::Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-9);
  BOLO_FUZZ_CHECK(std::abs(r.determinant() - 1.0) < 1e-9);
}

// Nine decimals: absolute rounding of 5e-10, plus the double's own relative precision.
bool close(double a, double b) { return std::abs(a - b) <= 1e-9 + 1e-14 * std::abs(a); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = fuzz::scratch_dir() / "poses.tum";
  fuzz::write_file(file, std::span(data, size));
  std::vector<odo::StampedPose> poses;
  try {
    poses = odo::read_tum(file);
  } catch (const odo::Error&) {
    return 0;
  }
  bool times_survive_printing = true;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const odo::StampedPose& p = poses[i];
    BOLO_FUZZ_CHECK(std::isfinite(p.t));
    BOLO_FUZZ_CHECK(i == 0 || p.t > poses[i - 1].t);
    if (i > 0 && p.t - poses[i - 1].t < 1e-8) times_survive_printing = false;
    if (std::abs(p.t) > 1e6) times_survive_printing = false;  // beyond nine decimals of a double
    for (int k = 0; k < 3; ++k) BOLO_FUZZ_CHECK(std::isfinite(p.T_wc.t(k)));
    check_proper_rotation(p.T_wc.R);
  }
  if (!times_survive_printing) return 0;

  std::string text;
  for (const odo::StampedPose& p : poses) text += odo::tum_line(p);
  const std::filesystem::path copy = fuzz::scratch_dir() / "poses-copy.tum";
  fuzz::write_file(copy, text);
  std::vector<odo::StampedPose> again;
  try {
    again = odo::read_tum(copy);
  } catch (const odo::Error& e) {
    std::fprintf(stderr, "accepted poses did not round-trip: %s\n", e.what());
    BOLO_FUZZ_CHECK(!"poses read from a TUM file were refused when written and read back");
  }
  BOLO_FUZZ_CHECK(again.size() == poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    BOLO_FUZZ_CHECK(close(poses[i].t, again[i].t));
    for (int k = 0; k < 3; ++k) BOLO_FUZZ_CHECK(close(poses[i].T_wc.t(k), again[i].T_wc.t(k)));
    BOLO_FUZZ_CHECK((poses[i].T_wc.R - again[i].T_wc.R).cwiseAbs().maxCoeff() < 1e-8);
  }
  return 0;
}
