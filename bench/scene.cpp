#include "scene.hpp"

#include <algorithm>
#include <cmath>

namespace bolo::bench {
namespace {

// splitmix64: tiny, deterministic, identical everywhere.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  // Roughly normal, unit variance (Irwin-Hall with four terms).
  double normal() {
    const double s = uniform() + uniform() + uniform() + uniform();
    return (s - 2.0) * 1.7320508075688772;  // sqrt(12 / 4)
  }

 private:
  std::uint64_t state_;
};

constexpr double kBackground = 7200.0;  // counts at the bottom of the frame
constexpr double kGradient = 1400.0;    // cooler sky at the top
constexpr double kTemporalSigma = 14.0;
constexpr double kPixelFpnSigma = 45.0;
constexpr double kColumnFpnSigma = 20.0;
constexpr std::uint16_t kMax14 = 0x3FFF;

struct Blob {
  double x, y, radius, amplitude, dx;  // centre and size as fractions of the width; dx per frame
};

}  // namespace

BenchData make_bench_data(std::uint32_t width, std::uint32_t height, std::size_t count) {
  BenchData d;
  d.width = width;
  d.height = height;
  const std::size_t n = std::size_t{width} * height;
  Rng rng(0xB010'0000ull ^ (std::uint64_t{width} << 20) ^ height);

  // Fixed pattern: per column and per pixel, the same in every frame.
  std::vector<double> column(width);
  for (double& c : column) c = rng.normal() * kColumnFpnSigma;
  std::vector<double> fpn(n);
  for (double& f : fpn) f = rng.normal() * kPixelFpnSigma;

  // The NUC that (roughly) undoes a gain non-uniformity, and the bad-pixel mask.
  d.nuc_gain_q14.resize(n);
  d.nuc_offset.resize(n);
  d.bad_mask.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double g = 1.0 + (rng.uniform() - 0.5) * 0.06;
    d.nuc_gain_q14[i] = static_cast<std::uint16_t>(std::lround(g * 16384.0));
    d.nuc_offset[i] = static_cast<std::int16_t>(std::lround(-fpn[i] * 0.8 + (rng.uniform() - 0.5) * 20.0));
    if (rng.next() % 1000 == 0) d.bad_mask[i] = 1;
  }
  // A few stuck pixels at either rail (about 1 in 10^4), the same in every frame.
  std::vector<std::size_t> stuck_high, stuck_low;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t r = rng.next() % 20000;
    if (r == 0) stuck_high.push_back(i);
    if (r == 1) stuck_low.push_back(i);
  }

  const Blob blobs[] = {{0.30, 0.55, 0.08, 2600.0, 0.004},
                        {0.68, 0.40, 0.05, 4200.0, -0.006},
                        {0.50, 0.80, 0.15, 900.0, 0.002}};
  const double w = static_cast<double>(width);
  const double h = static_cast<double>(height);
  d.frames.resize(count);
  for (std::size_t f = 0; f < count; ++f) {
    std::vector<std::uint16_t>& frame = d.frames[f];
    frame.resize(n);
    for (std::uint32_t y = 0; y < height; ++y) {
      const double fy = (static_cast<double>(y) + 0.5) / h;
      const double base = kBackground - kGradient * (1.0 - fy);
      for (std::uint32_t x = 0; x < width; ++x) {
        const double fx = (static_cast<double>(x) + 0.5) / w;
        double v = base + column[x];
        for (const Blob& b : blobs) {
          const double cx = b.x + b.dx * static_cast<double>(f);
          const double ddx = (fx - cx);
          const double ddy = (fy - b.y) * h / w;  // round blobs whatever the aspect ratio
          v += b.amplitude * std::exp(-(ddx * ddx + ddy * ddy) / (b.radius * b.radius));
        }
        const std::size_t i = std::size_t{y} * width + x;
        v += fpn[i] + rng.normal() * kTemporalSigma;
        frame[i] = static_cast<std::uint16_t>(std::clamp(std::lround(v), 1L, long{kMax14} - 1));
      }
    }
    for (std::size_t i : stuck_high) frame[i] = kMax14;
    for (std::size_t i : stuck_low) frame[i] = 0;
  }
  return d;
}

}  // namespace bolo::bench
