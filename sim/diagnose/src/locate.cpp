#include "checkerboard.hpp"
#include "locate.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <numeric>
#include <sstream>
#include <string_view>

#include "moving_edges.hpp"
#include "noisy_pixels.hpp"
#include "bolo/effects/stats.hpp"

namespace bolo::diag {
namespace {

struct Profiles {
  std::vector<double> frame_mean, frame_rms, col, row, pixel_mean, pixel_count;
  double var = 0;
};

Profiles profiles(const DiagnoseData& d, const std::vector<float>& r) {
  Profiles s;
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  s.frame_mean.assign(N, 0);
  s.frame_rms.assign(N, 0);
  s.pixel_mean.assign(P, 0);
  s.pixel_count.assign(P, 0);
  double total = 0, sse = 0;
  for (int n = 0; n < N; ++n) {
    const float* f = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    double a = 0, b = 0, c = 0;
    for (std::size_t p = 0; p < P; ++p)
      if (v[p]) { a += f[p]; b += double(f[p]) * f[p]; c += 1; s.pixel_mean[p] += f[p]; s.pixel_count[p] += 1; }
    s.frame_mean[n] = c > 0 ? a / c : 0;
    s.frame_rms[n] = c > 0 ? std::sqrt(b / c) : 0;
    total += c;
    sse += b;
  }
  s.var = total > 0 ? sse / total : 0;
  for (std::size_t p = 0; p < P; ++p)
    if (s.pixel_count[p] > 0) s.pixel_mean[p] /= s.pixel_count[p];
  s.col.assign(W, 0);
  s.row.assign(H, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) { s.col[x] += s.pixel_mean[y * W + x] / H; s.row[y] += s.pixel_mean[y * W + x] / W; }
  return s;
}

// Pooled correlation of the residual with a regressor given per pixel-frame.
template <typename F>
double correlation(const DiagnoseData& d, const std::vector<float>& r, F regressor) {
  const std::size_t P = d.shape.pixels();
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, n = 0;
  for (int f = 1; f < d.shape.n; ++f) {
    const std::uint8_t* v = d.valid_frame(f);
    const float* rf = d.frame(r, f);
    for (std::size_t p = f % 5; p < P; p += 5) {
      if (!v[p]) continue;
      const double x = regressor(f, p), y = rf[p];
      sx += x; sy += y; sxx += x * x; syy += y * y; sxy += x * y; n += 1;
    }
  }
  const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
  return vx > 0 && vy > 0 ? (sxy - sx * sy / n) / std::sqrt(vx * vy) : 0.0;
}

std::vector<int> input_steps(const DiagnoseData& d) {
  // Frames where the baseline changes most (top few, separated): "after steps".
  const std::size_t P = d.shape.pixels();
  std::vector<std::pair<double, int>> change;
  for (int n = 1; n < d.shape.n; ++n) {
    const float *b = d.frame(d.baseline, n), *bp = d.frame(d.baseline, n - 1);
    double s = 0;
    for (std::size_t p = 0; p < P; p += 3) s += std::fabs(b[p] - bp[p]);
    change.push_back({s, n});
  }
  std::sort(change.rbegin(), change.rend());
  std::vector<int> steps;
  for (auto [s, n] : change) {
    if (s <= 0 || steps.size() >= 8) break;
    bool far = true;
    for (int m : steps) far = far && std::abs(m - n) > 10;
    if (far) steps.push_back(n);
  }
  return steps;
}

nlohmann::json event_locked(const std::vector<double>& series, const std::vector<int>& events, int before, int after) {
  std::vector<double> sum(before + after + 1, 0.0), count(before + after + 1, 0.0);
  for (int e : events)
    for (int k = -before; k <= after; ++k) {
      const int n = e + k;
      if (n < 0 || n >= int(series.size())) continue;
      sum[k + before] += series[n];
      count[k + before] += 1;
    }
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < sum.size(); ++i) out.push_back(count[i] > 0 ? sum[i] / count[i] : 0.0);
  return {{"lags", nlohmann::json{-before, after}}, {"mean", out}, {"events", events}};
}

}  // namespace

nlohmann::json locate(const DiagnoseData& d, const std::vector<float>& r, const Blocks&) {
  const Profiles s = profiles(d, r);
  const int N = d.shape.n, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  nlohmann::json j;
  j["frame_mean"] = s.frame_mean;
  j["frame_rms"] = s.frame_rms;
  j["column_profile"] = s.col;
  j["row_profile"] = s.row;
  // Periodogram of the frame-mean residual (a plain DFT: N is a few hundred).
  std::vector<double> power;
  const double mean = std::accumulate(s.frame_mean.begin(), s.frame_mean.end(), 0.0) / N;
  for (int k = 1; k <= N / 2; ++k) {
    std::complex<double> acc = 0;
    for (int n = 0; n < N; ++n) acc += (s.frame_mean[n] - mean) * std::polar(1.0, -2 * M_PI * k * n / N);
    power.push_back(std::norm(acc) / N);
  }
  j["spectrum"] = {{"frequency_hz_step", d.fps / N}, {"power", power}};
  std::vector<int> flagged;
  for (int n = 0; n < N; ++n)
    if (d.flagged_event[n]) flagged.push_back(n);
  j["after_shutter_events"] = event_locked(s.frame_mean, flagged, 5, 20);
  const std::vector<double>& rms = s.frame_rms;
  j["after_input_steps"] = event_locked(rms, input_steps(d), 3, 15);
  // Correlations with physical regressors.
  nlohmann::json corr;
  const float* B = d.baseline.data();
  corr["input_change"] = correlation(d, r, [&](int f, std::size_t p) { return double(B[f * P + p]) - B[(f - 1) * P + p]; });
  corr["lagged_input_2"] = correlation(d, r, [&](int f, std::size_t p) {
    return f >= 2 ? double(B[(f - 2) * P + p]) - B[f * P + p] : 0.0; });
  corr["row_x_derivative"] = correlation(d, r, [&](int f, std::size_t p) {
    return double(p / W) * (double(B[f * P + p]) - B[(f - 1) * P + p]); });
  corr["level"] = correlation(d, r, [&](int f, std::size_t p) { return double(B[f * P + p]) - d.level_mid; });
  corr["laplacian"] = correlation(d, r, [&](int f, std::size_t p) {
    const int x = int(p % W), y = int(p / W);
    if (x == 0 || y == 0 || x == W - 1 || y == d.shape.height - 1) return 0.0;
    const float* b = B + std::size_t(f) * P;
    return 0.25 * (b[p - 1] + b[p + 1] + b[p - W] + b[p + W]) - b[p]; });
  bool temps = true;
  for (const auto& t : d.fpa_temp_c) temps = temps && t.has_value();
  if (temps) corr["fpa_temp_c"] = correlation(d, r, [&](int f, std::size_t) { return *d.fpa_temp_c[f]; });
  std::vector<double> since(N, 0.0);
  double last = d.t_s[0];
  for (int n = 0; n < N; ++n) { if (d.flagged_event[n]) last = d.t_s[n]; since[n] = d.t_s[n] - last; }
  corr["time_since_event"] = correlation(d, r, [&](int f, std::size_t) { return since[f]; });
  j["correlations"] = corr;
  // Frames identical to their predecessor (a sensor with noise never repeats a frame).
  std::vector<int> repeats;
  for (int n = 1; n < N; ++n) {
    const float *y = d.frame(d.recorded, n), *yp = d.frame(d.recorded, n - 1);
    std::size_t same = 0;
    for (std::size_t p = 0; p < P; ++p) same += y[p] == yp[p];
    if (same >= P - P / 1000) repeats.push_back(n);
  }
  j["repeated_frames"] = repeats;
  return j;
}

namespace {

// The pixel noise of the residual from 2x2 checkerboard differences (r00 - r01 - r10 + r11) / 2
// of valid pixels: white noise keeps its variance, while anything constant along rows or along
// columns, or smooth over two pixels, cancels (so bands or stripes do not count as noise here).
double checkerboard_sigma(const DiagnoseData& d, const std::vector<float>& r) {
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  std::vector<float> c;
  const int step = std::max(1, N / 64);
  for (int n = 0; n < N; n += step) {
    const float* rn = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    for (int y = 0; y + 1 < H; y += 2)
      for (int x = 0; x + 1 < W; x += 2) {
        const std::size_t p = std::size_t(y) * W + x;
        if (!(v[p] && v[p + 1] && v[p + W] && v[p + W + 1])) continue;
        c.push_back(std::fabs(checkerboard_difference(rn, p, std::size_t(W))));
      }
  }
  if (c.size() < 64) return 0.0;
  return 1.4826 * median_in_place(c);
}

// 4. A pattern along rows (or columns) that changes from frame to frame: bands that move, line
// flicker. Per frame, the median of each row of the residual, less that row's median over time
// (a static row pattern is row_fpn's) and the frame's median over rows (a global change is item
// 2's). A moving object covers few pixels of a row and leaves its median alone; a band covers the
// row. Only pixels where the baseline holds still since the previous frame count: a moving
// horizontal edge spans a row, and the baseline's small misses on it would read as a band. Against
// white noise of sigma (checkerboard_sigma), a row median over m pixels varies by about
// pi/2 sigma^2 / m: the excess over that, pooled over frames and rows, is the evidence, and its
// size (the RMS beyond the noise) must be a visible share of the noise floor.
bool moving_line_pattern(const DiagnoseData& d, const std::vector<float>& r, bool along_rows, double noise_floor,
                         Unexplained& u) {
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  const int lines = along_rows ? H : W, length = along_rows ? W : H;
  if (N < 8 || lines < 8 || length < 8) return false;
  const double sigma = checkerboard_sigma(d, r);
  if (!(sigma > 0)) return false;
  constexpr float kMissing = 3.4e38f;
  std::vector<float> med(std::size_t(N) * lines, kMissing), values;
  std::vector<double> counted(std::size_t(N) * lines, 0);
  for (int n = 1; n < N; ++n) {
    const float* rn = d.frame(r, n);
    const float *b = d.frame(d.baseline, n), *b0 = d.frame(d.baseline, n - 1);
    const std::uint8_t* v = d.valid_frame(n);
    for (int l = 0; l < lines; ++l) {
      values.clear();
      for (int k = 0; k < length; ++k) {
        const std::size_t p = along_rows ? std::size_t(l) * W + k : std::size_t(k) * W + l;
        if (v[p] && std::fabs(b[p] - b0[p]) < 0.5 * sigma) values.push_back(rn[p]);
      }
      if (int(values.size()) * 2 < length) continue;  // mostly masked: no median worth comparing
      counted[std::size_t(n) * lines + l] = double(values.size());
      med[std::size_t(n) * lines + l] = median_in_place(values);
    }
  }
  std::vector<float> line_level(lines, 0), frame_level(N, 0);
  for (int l = 0; l < lines; ++l) {
    values.clear();
    for (int n = 0; n < N; ++n) if (med[std::size_t(n) * lines + l] != kMissing) values.push_back(med[std::size_t(n) * lines + l]);
    line_level[l] = median_in_place(values);
  }
  for (int n = 0; n < N; ++n) {
    values.clear();
    for (int l = 0; l < lines; ++l)
      if (med[std::size_t(n) * lines + l] != kMissing) values.push_back(med[std::size_t(n) * lines + l] - line_level[l]);
    frame_level[n] = median_in_place(values);
  }
  double chi2 = 0, dof = 0, ss = 0, noise_ss = 0;
  std::vector<double> line_excess(lines, 0.0);
  for (int n = 0; n < N; ++n)
    for (int l = 0; l < lines; ++l) {
      const std::size_t i = std::size_t(n) * lines + l;
      if (med[i] == kMissing) continue;
      const double dev = med[i] - line_level[l] - frame_level[n];
      const double expected = M_PI / 2 * sigma * sigma / counted[i];
      chi2 += dev * dev / expected;
      dof += 1;
      ss += dev * dev;
      noise_ss += expected;
      line_excess[l] += dev * dev - expected;
    }
  if (dof < 64) return false;
  // Two medians taken out (per line over time, per frame over lines): slightly fewer degrees of
  // freedom than cells, which only makes the test stricter.
  const double z = (chi2 - dof) / std::sqrt(2 * dof);
  const double rms = std::sqrt(std::max(0.0, ss - noise_ss) / dof);  // beyond the noise
  if (!(z > 12 && rms > 0.2 * noise_floor)) return false;
  // Where: the lines whose excess is at least a quarter of the largest.
  const double top = *std::max_element(line_excess.begin(), line_excess.end());
  int first = lines, last = -1;
  for (int l = 0; l < lines; ++l)
    if (line_excess[l] >= 0.25 * top) first = std::min(first, l), last = std::max(last, l);
  u.where.frames = {{0, N - 1}};
  u.where.row0 = along_rows ? first : 0;
  u.where.row1 = along_rows ? last : H - 1;
  u.where.col0 = along_rows ? 0 : first;
  u.where.col1 = along_rows ? W - 1 : last;
  std::ostringstream t;
  t << (along_rows ? "rows " : "columns ") << first << "-" << last << ": a pattern along the "
    << (along_rows ? "rows" : "columns") << " that changes from frame to frame (moving bands, line flicker; "
    << (along_rows ? "row" : "column") << " medians of the residual vary by " << std::setprecision(3) << rms
    << " RMS beyond a pixel noise of " << sigma << ")";
  u.where.summary = t.str();
  u.rms = rms;
  return true;
}

// The frames in which a pattern of the time-averaged residual (pixel_mean over where's box) is
// present: each frame's residual projected onto the pattern (1 where the pattern is at its mean
// strength), smoothed over a few frames. All frames when the pattern holds throughout; the
// ranges where it is when it comes and goes (an object missing from the scene for a while).
std::vector<std::pair<int, int>> pattern_frames(const DiagnoseData& d, const std::vector<float>& r, const Where& where,
                                                const std::vector<double>& pixel_mean) {
  const int N = d.shape.n, W = d.shape.width;
  const std::vector<std::pair<int, int>> all = {{0, N - 1}};
  std::vector<double> strength(N, 0.0);
  for (int n = 0; n < N; ++n) {
    const float* rn = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    double rm = 0, mm = 0;
    for (int y = where.row0; y <= where.row1; ++y)
      for (int x = where.col0; x <= where.col1; ++x) {
        const std::size_t p = std::size_t(y) * W + x;
        if (!v[p]) continue;
        rm += double(rn[p]) * pixel_mean[p];
        mm += pixel_mean[p] * pixel_mean[p];
      }
    strength[n] = mm > 0 ? rm / mm : 0.0;
  }
  const int w = std::max(1, N / 50);
  std::vector<double> smooth(N, 0.0);
  for (int n = 0; n < N; ++n) {
    double s = 0, c = 0;
    for (int m = std::max(0, n - w); m <= std::min(N - 1, n + w); ++m) { s += strength[m]; c += 1; }
    smooth[n] = s / c;
  }
  const double peak = *std::max_element(smooth.begin(), smooth.end());
  if (!(peak > 0)) return all;
  std::vector<std::pair<int, int>> ranges;
  double inside = 0, outside = 0;
  int in_count = 0;
  for (int n = 0; n < N; ++n) {
    if (smooth[n] < 0.5 * peak) { outside += strength[n]; continue; }
    inside += strength[n];
    ++in_count;
    if (!ranges.empty() && n - ranges.back().second <= w + 1) ranges.back().second = n;
    else ranges.push_back({n, n});
  }
  // Only a clear on/off: present in at most 80 % of the frames, in few ranges, and at most a
  // quarter as strong elsewhere.
  const int out_count = N - in_count;
  if (ranges.empty() || ranges.size() > 4 || in_count > 0.8 * N || out_count == 0) return all;
  if (outside / out_count > 0.25 * inside / in_count) return all;
  return ranges;
}

constexpr std::string_view kStaticPattern = "static pattern in the time-averaged residual";

std::string frames_text(const std::vector<std::pair<int, int>>& ranges) {
  std::ostringstream t;
  for (std::size_t i = 0; i < ranges.size(); ++i) t << (i ? ", " : "") << ranges[i].first << "-" << ranges[i].second;
  return t.str();
}

}  // namespace

std::vector<Unexplained> find_unexplained(const DiagnoseData& d, const std::vector<float>& r, const Blocks& blocks,
                                          double noise_floor) {
  std::vector<Unexplained> out;
  const Profiles s = profiles(d, r);
  // 0. Repeated frames no finding took (too few for a held-out period, say).
  if (d.shape.n > 1) {
    const std::size_t P = d.shape.pixels();
    Unexplained u;
    double total = 0, count = 0;
    for (int n = 1; n < d.shape.n; ++n) {
      const float *y = d.frame(d.recorded, n), *yp = d.frame(d.recorded, n - 1), *rn = d.frame(r, n);
      std::size_t same = 0;
      double rr = 0;
      for (std::size_t p = 0; p < P; ++p) { same += y[p] == yp[p]; rr += double(rn[p]) * rn[p]; }
      // A repeat the findings explain leaves no residual; one they do not, does.
      if (same >= P - P / 1000 && rr > 0) {
        u.where.frames.push_back({n - 1, n});
        total += rr;
        count += double(P);
      }
    }
    if (!u.where.frames.empty()) {
      u.where.row1 = d.shape.height - 1;
      u.where.col1 = d.shape.width - 1;
      u.where.summary = std::to_string(u.where.frames.size()) + " frame(s) bit-identical to their predecessor";
      u.rms = std::sqrt(total / count);
      out.push_back(u);
    }
  }
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  const double sigma = std::sqrt(s.var);
  if (!(sigma > 0)) return out;
  // 1. Blocks of frames with a residual well above the rest.
  std::vector<double> block_ms(blocks.count, 0.0), block_n(blocks.count, 0.0);
  for (int n = 0; n < N; ++n) { block_ms[blocks.block_of_frame[n]] += s.frame_rms[n] * s.frame_rms[n]; block_n[blocks.block_of_frame[n]] += 1; }
  std::vector<double> block_rms(blocks.count);
  for (int b = 0; b < blocks.count; ++b) block_rms[b] = std::sqrt(block_ms[b] / std::max(1.0, block_n[b]));
  const double typical = median_of(block_rms);
  const double limit = std::max(1.5 * typical, 1.5 * noise_floor);
  std::vector<std::pair<int, int>> ranges;
  double worst = 0;
  for (int n = 0; n < N; ++n) {
    if (block_rms[blocks.block_of_frame[n]] <= limit) continue;
    worst = std::max(worst, s.frame_rms[n]);
    if (!ranges.empty() && ranges.back().second == n - 1) ranges.back().second = n;
    else ranges.push_back({n, n});
  }
  if (!ranges.empty() && int(ranges.size()) < std::max(2, blocks.count / 2)) {
    Unexplained u;
    u.where.frames = ranges;
    u.where.row1 = H - 1;
    u.where.col1 = W - 1;
    u.where.summary = "frames whose residual is well above the rest of the recording";
    u.rms = worst;
    out.push_back(u);
  }
  // 2. Global per-frame fluctuation beyond what pixel noise averages to.
  double vm = 0, mm = 0;
  for (double m : s.frame_mean) { vm += m * m; mm += m; }
  vm = vm / N - (mm / N) * (mm / N);
  const double per_frame_noise = s.var / (double(d.shape.pixels()) * 0.9);
  if (N >= 8 && vm > 9 * per_frame_noise && std::sqrt(vm) > 0.1 * noise_floor) {
    Unexplained u;
    u.where.frames = {{0, N - 1}};
    u.where.row1 = H - 1;
    u.where.col1 = W - 1;
    u.where.summary = "frame-to-frame global offset fluctuation (whole-frame residual mean varies)";
    u.rms = std::sqrt(vm);
    out.push_back(u);
  }
  // 3. Static regions: 8x8 tiles of the time-averaged residual far beyond their noise.
  const int th = std::max(1, H / 8), tw = std::max(1, W / 8);
  std::vector<Unexplained> tiles;
  for (int ty = 0; ty < H; ty += th)
    for (int tx = 0; tx < W; tx += tw) {
      double z2 = 0, m = 0, ms = 0;
      for (int y = ty; y < std::min(H, ty + th); ++y)
        for (int x = tx; x < std::min(W, tx + tw); ++x) {
          const std::size_t p = std::size_t(y) * W + x;
          if (s.pixel_count[p] < 2) continue;
          const double z = s.pixel_mean[p] / (sigma / std::sqrt(s.pixel_count[p]));
          z2 += z * z;
          ms += s.pixel_mean[p] * s.pixel_mean[p];
          m += 1;
        }
      if (m < 4) continue;
      if ((z2 - m) / std::sqrt(2 * m) > 12 && std::sqrt(ms / m) > 0.2 * noise_floor) {
        Unexplained u;
        u.where.frames = {{0, N - 1}};
        u.where.row0 = ty; u.where.row1 = std::min(H, ty + th) - 1;
        u.where.col0 = tx; u.where.col1 = std::min(W, tx + tw) - 1;
        std::ostringstream t;
        t << kStaticPattern << ", rows " << u.where.row0 << "-" << u.where.row1 << ", cols "
          << u.where.col0 << "-" << u.where.col1;
        u.where.summary = t.str();
        u.rms = std::sqrt(ms / m);
        tiles.push_back(u);
      }
    }
  if (tiles.size() > 4) {
    // Many tiles: one static pattern over their bounding box.
    Unexplained all = tiles.front();
    for (const Unexplained& t : tiles) {
      all.where.row0 = std::min(all.where.row0, t.where.row0);
      all.where.row1 = std::max(all.where.row1, t.where.row1);
      all.where.col0 = std::min(all.where.col0, t.where.col0);
      all.where.col1 = std::max(all.where.col1, t.where.col1);
      all.rms = std::max(all.rms, t.rms);
    }
    std::ostringstream t;
    t << kStaticPattern << " over " << tiles.size() << " of 64 tiles, rows "
      << all.where.row0 << "-" << all.where.row1 << ", cols " << all.where.col0 << "-" << all.where.col1;
    all.where.summary = t.str();
    tiles = {all};
  }
  for (Unexplained& t : tiles) {
    t.where.frames = pattern_frames(d, r, t.where, s.pixel_mean);
    if (t.where.frames.size() == 1 && t.where.frames[0] == std::pair<int, int>{0, N - 1}) continue;
    // Present only for a while: not static. Its size is still the time average's.
    t.where.summary = "pattern in the residual present only in frames " + frames_text(t.where.frames) +
                      t.where.summary.substr(kStaticPattern.size());
  }
  out.insert(out.end(), tiles.begin(), tiles.end());
  for (const bool along_rows : {true, false}) {
    Unexplained u;
    if (moving_line_pattern(d, r, along_rows, noise_floor, u)) out.push_back(u);
  }
  if (Unexplained u; noisy_pixels(d, r, u)) out.push_back(u);
  if (Unexplained u; moving_edge_residual(d, r, noise_floor, u)) out.push_back(u);
  return out;
}

}  // namespace bolo::diag
