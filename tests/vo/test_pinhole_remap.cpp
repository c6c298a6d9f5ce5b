// The resampling of a distorted camera's frames onto the VO's pinhole (bolo::odo::PinholeRemap)
// and the distortion check it relies on (sim::scene::distortion_problem).

#include <cmath>
#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/odometry/pinhole_remap.hpp"

using namespace bolo;

namespace {

sim::scene::Camera lens(double k1, double k2, double p1 = 0, double p2 = 0) {
  sim::scene::Camera c(160, 120, 50.0);
  c.k1 = k1, c.k2 = k2, c.p1 = p1, c.p2 = p2;
  return c;
}

// A smooth pattern over the undistorted normalised image plane, in counts.
double pattern(double x, double y) { return 8000.0 + 900.0 * std::sin(9.0 * x + 1.0) * std::cos(7.0 * y - 0.5); }

// What the distorted camera records of that pattern, rounded to counts.
std::vector<std::uint16_t> recorded(const sim::scene::Camera& c) {
  std::vector<std::uint16_t> frame(std::size_t{c.width} * c.height);
  for (std::uint32_t v = 0; v < c.height; ++v)
    for (std::uint32_t u = 0; u < c.width; ++u) {
      const Eigen::Vector2d n = c.undistort({(u - c.cx) / c.fx, (v - c.cy) / c.fy});
      frame[std::size_t{v} * c.width + u] = static_cast<std::uint16_t>(std::lround(pattern(n.x(), n.y())));
    }
  return frame;
}

// The largest difference between the remapped frame and the pattern seen by the pinhole, over
// the pixels at least `margin` from the border.
double worst_error(const odo::PinholeRemap& remap, const sim::scene::Camera& c, std::uint32_t margin) {
  const std::vector<std::uint16_t> in = recorded(c);
  std::vector<std::uint16_t> out(in.size());
  remap.apply(in, out);
  const vo::Camera& k = remap.pinhole();
  double worst = 0;
  for (std::uint32_t v = margin; v + margin < c.height; ++v)
    for (std::uint32_t u = margin; u + margin < c.width; ++u) {
      const double expected = pattern((u - k.cx) / k.fx, (v - k.cy) / k.fy);
      worst = std::max(worst, std::fabs(out[std::size_t{v} * c.width + u] - expected));
    }
  return worst;
}

}  // namespace

TEST_CASE("pinhole remap: no distortion passes frames unchanged", "[vo][remap]") {
  const sim::scene::Camera c = lens(0, 0);
  const odo::PinholeRemap remap(c);
  CHECK(remap.identity());
  CHECK(remap.focal_scale() == 1.0);
  CHECK(remap.pinhole().fx == static_cast<float>(c.fx));
  const std::vector<std::uint16_t> in = recorded(c);
  std::vector<std::uint16_t> out(in.size());
  remap.apply(in, out);
  CHECK(out == in);
}

TEST_CASE("pinhole remap: a barrel lens's frames match the pinhole's view", "[vo][remap]") {
  const sim::scene::Camera c = lens(-0.25, 0.05);
  const odo::PinholeRemap remap(c);
  CHECK_FALSE(remap.identity());
  CHECK(remap.focal_scale() == 1.0);  // barrel distortion only crops the periphery
  // The distorted frame's top row differs from the pinhole's view by up to ~370 counts; after
  // the remap what is left is the cubic's interpolation of a pattern with ~20-pixel periods
  // (measured: 1.0 counts).
  const std::vector<std::uint16_t> raw = recorded(c);
  double unresampled = 0;
  for (std::uint32_t u = 0; u < c.width; ++u)
    unresampled = std::max(unresampled, std::fabs(raw[u] - pattern((u - c.cx) / c.fx, (0 - c.cy) / c.fy)));
  CHECK(unresampled > 200);
  CHECK(worst_error(remap, c, 2) < 3);
}

TEST_CASE("pinhole remap: a lens with OpenCV's rational model (the Optris PI450's coefficients)", "[vo][remap]") {
  // Read as Brown-Conrady alone (k1, k2) this lens folds inside the image; the denominator
  // (k4..k6) keeps it one-to-one and barrel.
  sim::scene::Camera c = lens(-0.19666214082095448, -1.8316527667010765, 4.14886277407486e-05, -0.0004457029653203337);
  c.k3 = 5.431916500757228, c.k4 = 0.2761986355556445, c.k5 = -2.4816640836747377, c.k6 = 6.667848761560231;
  const odo::PinholeRemap remap(c);
  CHECK_FALSE(remap.identity());
  CHECK(remap.focal_scale() == 1.0);
  CHECK(worst_error(remap, c, 2) < 3);
}

TEST_CASE("pinhole remap: a pincushion lens gets a longer focal length and stays inside the frame", "[vo][remap]") {
  const sim::scene::Camera c = lens(0.15, 0.0, 0.002, -0.001);
  const odo::PinholeRemap remap(c);
  CHECK(remap.focal_scale() > 1.02);
  CHECK(remap.focal_scale() < 1.2);
  CHECK(remap.pinhole().fx == Approx(c.fx * remap.focal_scale()).epsilon(1e-6));
  CHECK(remap.pinhole().cx == static_cast<float>(c.cx));
  // Every output pixel, corners included, reads the pattern where the pinhole sees it
  // (measured: 2.9 counts, at the border where the cubic's taps are clamped).
  CHECK(worst_error(remap, c, 0) < 6);
}

TEST_CASE("pinhole remap: the resampling is linear up to rounding", "[vo][remap]") {
  // The two-frame model raw_i = alpha raw_{i-1} + beta u holds on the output because of this.
  const sim::scene::Camera c = lens(-0.2, 0.03);
  const odo::PinholeRemap remap(c);
  const std::size_t n = std::size_t{c.width} * c.height;
  std::vector<std::uint16_t> a(n), b(n), sum(n), ra(n), rb(n), rsum(n);
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = static_cast<std::uint16_t>(4000 + (i * 7919) % 3001);
    b[i] = static_cast<std::uint16_t>(2000 + (i * 104729) % 1999);
    sum[i] = static_cast<std::uint16_t>(a[i] + b[i]);
  }
  remap.apply(a, ra), remap.apply(b, rb), remap.apply(sum, rsum);
  int worst = 0;
  for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, std::abs(int{rsum[i]} - int{ra[i]} - int{rb[i]}));
  CHECK(worst <= 1);
}

TEST_CASE("pinhole remap: distortions that fold are refused", "[vo][remap]") {
  CHECK(sim::scene::distortion_problem(lens(0, 0)) == nullptr);
  CHECK(sim::scene::distortion_problem(lens(-0.25, 0.05)) == nullptr);
  const sim::scene::Camera folded = lens(-1.5, 0.0);
  REQUIRE(sim::scene::distortion_problem(folded) != nullptr);
  CHECK(std::string(sim::scene::distortion_problem(folded)).find("folds back inside the image") != std::string::npos);
  CHECK_THROWS_WITH(odo::PinholeRemap(folded), Catch::Contains("folds back"));
}
