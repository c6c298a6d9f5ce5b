#pragma once
// The small timing harness of bolo-bench: a monotonic clock, an optimisation barrier, robust
// statistics over repetitions, and the calibration that picks how many frames one repetition
// times. No third-party benchmark library: the figures that matter are ratios of measurements
// taken in the same run, so the harness only has to be honest, not clever.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bolo::bench {

using Clock = std::chrono::steady_clock;

// Tells the compiler the memory behind `p` is read and written here, so stores to it (and the
// work producing them) cannot be dropped or moved across the timed region.
inline void clobber_memory(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
  asm volatile("" : : "r"(p) : "memory");
#else
  static const void* volatile sink;
  sink = p;
#endif
}

// Something that processes whole frames: run(n) processes n frames.
class Workload {
 public:
  virtual ~Workload() = default;
  virtual void run(std::size_t frames) = 0;
};

inline double time_frames(Workload& w, std::size_t frames) {
  const Clock::time_point start = Clock::now();
  w.run(frames);
  const Clock::time_point stop = Clock::now();
  return std::chrono::duration<double>(stop - start).count();
}

// Frames per repetition so that one repetition lasts about `target_s`: doubles a trial batch until
// it runs for at least `probe_s`, then scales. Never fewer than `min_frames`.
inline std::size_t calibrate(Workload& w, double target_s, double probe_s, std::size_t min_frames) {
  std::size_t n = 1;
  double t = time_frames(w, n);
  while (t < probe_s && n < (std::size_t{1} << 24)) {
    n *= 2;
    t = time_frames(w, n);
  }
  const double per_frame = t / static_cast<double>(n);
  const double wanted = per_frame > 0 ? std::ceil(target_s / per_frame) : static_cast<double>(min_frames);
  const std::size_t frames = wanted > 1e7 ? std::size_t{10'000'000} : static_cast<std::size_t>(wanted);
  return std::max(frames, min_frames);
}

// Linear-interpolated quantile, q in [0, 1], of a copy of `values` (non-empty).
inline double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double pos = q * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  return values[lo] + (values[hi] - values[lo]) * frac;
}

inline double median(const std::vector<double>& values) { return quantile(values, 0.5); }

// One measured quantity: per-repetition rates (units per second) and their summary.
struct Series {
  std::vector<double> per_s;  // one entry per repetition
  double median_per_s() const { return median(per_s); }
  // Interquartile range relative to the median: a noise indicator, 0 on a quiet machine.
  double iqr_rel() const {
    const double m = median_per_s();
    return m > 0 ? (quantile(per_s, 0.75) - quantile(per_s, 0.25)) / m : 0.0;
  }
};

}  // namespace bolo::bench
