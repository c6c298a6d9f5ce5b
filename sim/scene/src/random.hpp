#pragma once
// Deterministic hashing, random numbers and value noise (portable: no <random> distributions,
// whose output differs between standard libraries).

#include <cmath>
#include <cstdint>

namespace bolo::sim::scene::detail {

constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// One finalising mix over a multiply-combined key: cheap, and well spread for seeds and cells.
constexpr std::uint64_t hash(std::uint64_t seed, std::uint64_t a) {
  return mix64(seed ^ (a * 0xD1B54A32D192ED03ull));
}
constexpr std::uint64_t hash(std::uint64_t seed, std::uint64_t a, std::uint64_t b) {
  return mix64(seed ^ (a * 0xD1B54A32D192ED03ull) ^ (b * 0xABA0B3C6D1C81A4Bull + 0x632BE59BD9B4E019ull));
}
constexpr std::uint64_t hash(std::uint64_t seed, std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return mix64(seed ^ (a * 0xD1B54A32D192ED03ull) ^ (b * 0xABA0B3C6D1C81A4Bull + 0x632BE59BD9B4E019ull) ^
               (c * 0x8CB92BA72F3D8DD7ull + 0x9E3779B97F4A7C15ull));
}

// [0, 1) from the top 53 bits.
constexpr double unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }
constexpr double signed_unit(std::uint64_t h) { return 2.0 * unit(h) - 1.0; }

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(mix64(seed ^ 0x5EED5EED5EED5EEDull)) {}
  std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ull;
    return mix64(state_);
  }
  double uniform() { return unit(next()); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(uniform() * static_cast<double>(hi - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t state_;
};

// floor() without a libm call (x86-64 baseline has no SSE4.1 round); |x| < 2^62.
inline double fast_floor(double x) {
  const double t = static_cast<double>(static_cast<std::int64_t>(x));
  return t > x ? t - 1.0 : t;
}
inline std::int64_t ifloor(double x) { return static_cast<std::int64_t>(fast_floor(x)); }
inline std::uint64_t u64(std::int64_t x) { return static_cast<std::uint64_t>(x); }

// Lattice value in [-1, 1].
inline double lattice(std::uint64_t seed, std::int64_t ix, std::int64_t iy) {
  std::uint64_t h = seed + u64(ix) * 0x9E3779B97F4A7C15ull + u64(iy) * 0xC2B2AE3D27D4EB4Full;
  h ^= h >> 31;
  h *= 0xD6E8FEB86659FD93ull;
  h ^= h >> 32;
  return signed_unit(h);
}

inline double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// Smooth 2D value noise in [-1, 1], feature size 1.
inline double value_noise(std::uint64_t seed, double x, double y) {
  const double fx = fast_floor(x), fy = fast_floor(y);
  const std::int64_t ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = fade(x - fx), ty = fade(y - fy);
  const double a = lattice(seed, ix, iy), b = lattice(seed, ix + 1, iy);
  const double c = lattice(seed, ix, iy + 1), d = lattice(seed, ix + 1, iy + 1);
  const double ab = a + (b - a) * tx, cd = c + (d - c) * tx;
  return ab + (cd - ab) * ty;
}

inline double smoothstep(double e0, double e1, double x) {
  double t = (x - e0) / (e1 - e0);
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace bolo::sim::scene::detail
