#include "moving_edges.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "bolo/effects/stats.hpp"

namespace bolo::diag {

namespace {

struct Moments {
  double sum = 0, squares = 0, count = 0;
  void add(double v) { sum += v; squares += v * v; count += 1; }
  double variance() const { return count > 1 ? (squares - sum * sum / count) / (count - 1) : 0.0; }
};

}  // namespace

bool moving_edge_residual(const DiagnoseData& d, const std::vector<float>& r, double noise_floor, Unexplained& u) {
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  if (!d.has_scene || N < 16 || !(noise_floor > 0)) return false;
  // A step of three noise sigmas in the simulated input is a change no noise makes.
  const double step = 3 * noise_floor;
  Moments still, changing;
  double masked = 0;
  const std::vector<std::uint8_t> all(d.unclipped.size() == d.shape.size() ? 0 : P, 1);
  auto readable = [&](int n) {
    return all.empty() ? d.unclipped.data() + std::size_t(n) * P : all.data();
  };
  std::vector<Moments> per_frame(N);
  int row0 = H, row1 = -1, col0 = W, col1 = -1;
  for (int n = 1; n < N; ++n) {
    const float *b = d.frame(d.still_reference(), n), *b0 = d.frame(d.still_reference(), n - 1), *rn = d.frame(r, n);
    if (d.flagged_event[n] || d.flagged_event[n - 1]) continue;
    // Readable pixel-frames, including those the baseline fit masked as misses at moving edges:
    // they are the largest part of such a residual, and no fit saw them.
    const std::uint8_t* v = readable(n);
    const std::uint8_t* v0 = readable(n - 1);
    const std::uint8_t* fitted = d.valid_frame(n);
    for (std::size_t p = 0; p < P; ++p) {
      if (!v[p] || !v0[p]) continue;
      if (holds_still(b[p], b0[p])) {
        still.add(rn[p]);
      } else if (std::fabs(double(b[p]) - b0[p]) > step) {
        changing.add(rn[p]);
        masked += fitted[p] ? 0 : 1;
        per_frame[n].add(rn[p]);
        const int y = int(p / std::size_t(W)), x = int(p % std::size_t(W));
        row0 = std::min(row0, y), row1 = std::max(row1, y);
        col0 = std::min(col0, x), col1 = std::max(col1, x);
      }
    }
  }
  if (still.count < 1000 || changing.count < 100) return false;
  const double v_still = still.variance(), v_changing = changing.variance();
  const double excess = v_changing - v_still;
  if (!(excess > 0)) return false;
  // Residuals at edges are correlated along the edge and from frame to frame, so the evidence is
  // how consistently blocks of frames show the excess (the per-pixel count would overstate it):
  // each block's excess over the still pixels' variance, as a t statistic across blocks.
  constexpr int kBlockFrames = 8;
  std::vector<double> block_excess;
  for (int first = 1; first < N; first += kBlockFrames) {
    Moments block;
    for (int n = first; n < std::min(N, first + kBlockFrames); ++n) {
      block.sum += per_frame[n].sum, block.squares += per_frame[n].squares, block.count += per_frame[n].count;
    }
    if (block.count >= 20) block_excess.push_back(block.variance() - v_still);
  }
  const double blocks = double(block_excess.size());
  if (blocks < 8) return false;
  double mean = 0, spread = 0;
  for (double e : block_excess) mean += e / blocks;
  for (double e : block_excess) spread += (e - mean) * (e - mean) / (blocks - 1);
  const double t_stat = spread > 0 ? mean / std::sqrt(spread / blocks) : 0.0;
  if (t_stat < 6 || std::sqrt(excess) < 0.2 * noise_floor) return false;
  // The frames that carry it: a frame's excess at least a quarter of the typical changing frame's.
  std::vector<double> excesses;
  for (int n = 1; n < N; ++n)
    if (per_frame[n].count >= 10) excesses.push_back(std::max(0.0, per_frame[n].variance() - v_still));
  std::sort(excesses.begin(), excesses.end());
  const double typical = excesses.empty() ? 0.0 : excesses[excesses.size() / 2];
  for (int n = 1; n < N; ++n) {
    if (per_frame[n].count < 10 || per_frame[n].variance() - v_still < 0.25 * typical) continue;
    if (!u.where.frames.empty() && u.where.frames.back().second >= n - 2) u.where.frames.back().second = n;
    else u.where.frames.push_back({n, n});
  }
  if (u.where.frames.size() > 12) u.where.frames = {{u.where.frames.front().first, u.where.frames.back().second}};
  u.where.row0 = row0, u.where.row1 = row1, u.where.col0 = col0, u.where.col1 = col1;
  u.rms = std::sqrt(excess);
  const double share = 100.0 * changing.count / (changing.count + still.count);
  std::ostringstream t;
  t.precision(2);
  t << std::fixed << "residual where the simulated input changes: " << u.rms << " RMS beyond the noise at the "
    << share << " % of pixel-frames where it steps by more than " << step
    << " counts";
  if (masked > 0) t << " (" << 100.0 * masked / changing.count << " % of them masked out of the fits as large misses)";
  t << "; a transient response the baseline lacks: motion within the exposure, a timing, a second time constant";
  u.where.summary = t.str();
  return true;
}

}  // namespace bolo::diag
