// Block-matching flow of the simulation input (scene_flow.hpp).

#include "bolo/effects/scene_flow.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bolo::diag {
namespace {

// Window radii (coarse: of 2x2 bins) and the fine search about the coarse match. Windows of 10
// and 7 pixels: on the demo scene's aliased disc, moving 6-7 pixels a frame, smaller windows
// matched its rim along itself (6 x 6 and 5 x 5 explained 79 % of a rolling readout's signature
// through the rate they give, 10 x 10 and 7 x 7 91 %).
constexpr int kCoarseRadius = 2, kFineRadius = 3, kFineReach = 1;

struct Image {
  int h = 0, w = 0;
  const float* v = nullptr;
  float at(int r, int c) const { return v[std::clamp(r, 0, h - 1) * w + std::clamp(c, 0, w - 1)]; }
};

// Sum of squared differences of next(x) against now(x - d) over the window about (r, c).
double window_ssd(const Image& now, const Image& next, int r, int c, int dy, int dx, int radius) {
  double s = 0;
  for (int i = -radius; i <= radius; ++i)
    for (int j = -radius; j <= radius; ++j) {
      const double e = double(next.at(r + i, c + j)) - now.at(r + i - dy, c + j - dx);
      s += e * e;
    }
  return s;
}

// Lower cost wins; within a relative whisker the shorter displacement does (uniform regions
// match at every shift).
struct Best {
  double cost = std::numeric_limits<double>::infinity();
  int dy = 0, dx = 0;
  void offer(double c, int y, int x) {
    const double tol = 1e-9 * std::max(1.0, cost == std::numeric_limits<double>::infinity() ? c : cost);
    if (c < cost - tol || (c <= cost + tol && y * y + x * x < dy * dy + dx * dx)) { cost = c; dy = y; dx = x; }
  }
};

void bin2(const float* src, int h, int w, std::vector<float>& dst) {
  const int h2 = h / 2, w2 = w / 2;
  dst.assign(std::size_t(h2) * w2, 0.0f);
  for (int r = 0; r < h2; ++r)
    for (int c = 0; c < w2; ++c)
      dst[std::size_t(r) * w2 + c] = 0.25f * (src[(2 * r) * w + 2 * c] + src[(2 * r) * w + 2 * c + 1] +
                                              src[(2 * r + 1) * w + 2 * c] + src[(2 * r + 1) * w + 2 * c + 1]);
}

// input[n](x - f (dy, dx)) - input[n](x), bilinear.
void advance_along_flow(const DiagnoseData& d, int n, double fraction, float* out) {
  const int H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  const Image now{H, W, d.frame(d.input, n)};
  const std::int8_t* fy = d.input_flow_dy.data() + std::size_t(n) * P;
  const std::int8_t* fx = d.input_flow_dx.data() + std::size_t(n) * P;
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      const std::size_t p = std::size_t(r) * W + c;
      if (fy[p] == 0 && fx[p] == 0) { out[p] = 0.0f; continue; }
      const double y = r - fraction * fy[p], x = c - fraction * fx[p];
      const int y0 = int(std::floor(y)), x0 = int(std::floor(x));
      const double wy = y - y0, wx = x - x0;
      const double v = (1 - wy) * ((1 - wx) * now.at(y0, x0) + wx * now.at(y0, x0 + 1)) +
                       wy * ((1 - wx) * now.at(y0 + 1, x0) + wx * now.at(y0 + 1, x0 + 1));
      out[p] = static_cast<float>(v - now.v[p]);
    }
}

}  // namespace

void fill_input_flow(DiagnoseData& d, int max_shift) {
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  d.input_flow_dy.assign(d.shape.size(), 0);
  d.input_flow_dx.assign(d.shape.size(), 0);
  if (H < 4 || W < 4) return;
  const int coarse_reach = std::max(1, (std::min(max_shift, 126) + 1) / 2);
  std::vector<float> now2, next2;
  std::vector<std::uint8_t> changed(P), near_change(P);
  for (int n = 0; n + 1 < N; ++n) {
    const float *a = d.frame(d.input, n), *b = d.frame(d.input, n + 1);
    bool any = false;
    for (std::size_t p = 0; p < P; ++p) {
      changed[p] = std::fabs(b[p] - a[p]) > 1e-6f * (std::fabs(a[p]) + std::fabs(b[p])) + 1e-12f;
      any = any || changed[p];
    }
    if (!any) continue;
    // A pixel whose window sees a change is matched.
    std::fill(near_change.begin(), near_change.end(), 0);
    const int k = kFineRadius;
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c)
        if (changed[std::size_t(r) * W + c])
          for (int i = std::max(0, r - k); i <= std::min(H - 1, r + k); ++i)
            std::fill_n(near_change.begin() + std::ptrdiff_t(i) * W + std::max(0, c - k), std::min(W - 1, c + k) - std::max(0, c - k) + 1, 1);
    bin2(a, H, W, now2);
    bin2(b, H, W, next2);
    const int h2 = H / 2, w2 = W / 2;
    const Image coarse_now{h2, w2, now2.data()}, coarse_next{h2, w2, next2.data()};
    std::vector<std::int8_t> coarse_dy(std::size_t(h2) * w2, 0), coarse_dx(std::size_t(h2) * w2, 0);
    for (int r = 0; r < h2; ++r)
      for (int c = 0; c < w2; ++c) {
        const std::size_t q = std::size_t(2 * r) * W + 2 * c;
        if (!(near_change[q] || near_change[q + 1] || near_change[q + W] || near_change[q + W + 1])) continue;
        Best best;
        for (int dy = -coarse_reach; dy <= coarse_reach; ++dy)
          for (int dx = -coarse_reach; dx <= coarse_reach; ++dx)
            best.offer(window_ssd(coarse_now, coarse_next, r, c, dy, dx, kCoarseRadius), dy, dx);
        coarse_dy[std::size_t(r) * w2 + c] = static_cast<std::int8_t>(best.dy);
        coarse_dx[std::size_t(r) * w2 + c] = static_cast<std::int8_t>(best.dx);
      }
    const Image fine_now{H, W, a}, fine_next{H, W, b};
    std::int8_t* fy = d.input_flow_dy.data() + std::size_t(n) * P;
    std::int8_t* fx = d.input_flow_dx.data() + std::size_t(n) * P;
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c) {
        if (!near_change[std::size_t(r) * W + c]) continue;
        const std::size_t q = std::size_t(std::min(r / 2, h2 - 1)) * w2 + std::min(c / 2, w2 - 1);
        const int cy = 2 * coarse_dy[q], cx = 2 * coarse_dx[q];
        Best best;
        best.offer(window_ssd(fine_now, fine_next, r, c, 0, 0, kFineRadius), 0, 0);
        for (int dy = cy - kFineReach; dy <= cy + kFineReach; ++dy)
          for (int dx = cx - kFineReach; dx <= cx + kFineReach; ++dx)
            if (std::abs(dy) <= 127 && std::abs(dx) <= 127 && (dy != 0 || dx != 0))
              best.offer(window_ssd(fine_now, fine_next, r, c, dy, dx, kFineRadius), dy, dx);
        fy[std::size_t(r) * W + c] = static_cast<std::int8_t>(best.dy);
        fx[std::size_t(r) * W + c] = static_cast<std::int8_t>(best.dx);
      }
  }
}

void subpixel_input_flow(const DiagnoseData& d, int n, std::vector<float>& dy, std::vector<float>& dx) {
  const int H = d.shape.height, W = d.shape.width;
  const std::size_t P = d.shape.pixels();
  dy.assign(P, 0.0f);
  dx.assign(P, 0.0f);
  if (n < 0 || n + 1 >= d.shape.n || d.input_flow_dy.size() != d.shape.size()) return;
  const float *a = d.frame(d.input, n), *b = d.frame(d.input, n + 1);
  const Image now{H, W, a}, next{H, W, b};
  const std::int8_t* fy = d.input_flow_dy.data() + std::size_t(n) * P;
  const std::int8_t* fx = d.input_flow_dx.data() + std::size_t(n) * P;
  // The vertex of the parabola through costs at -1, 0, +1 (0 is the minimum), within half a pixel.
  auto vertex = [](double minus, double centre, double plus) {
    const double curvature = minus + plus - 2 * centre;
    return curvature > 1e-12 * std::max(1.0, centre) ? std::clamp(0.5 * (minus - plus) / curvature, -0.5, 0.5) : 0.0;
  };
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      const std::size_t p = std::size_t(r) * W + c;
      const int y = fy[p], x = fx[p];
      if (y == 0 && x == 0 && !(std::fabs(b[p] - a[p]) > 1e-6f * (std::fabs(a[p]) + std::fabs(b[p])) + 1e-12f)) continue;
      auto cost = [&](int oy, int ox) { return window_ssd(now, next, r, c, y + oy, x + ox, kFineRadius); };
      const double centre = cost(0, 0);
      dy[p] = static_cast<float>(y + vertex(cost(-1, 0), centre, cost(1, 0)));
      dx[p] = static_cast<float>(x + vertex(cost(0, -1), centre, cost(0, 1)));
    }
}

bool delay_response(const DiagnoseData& d, double tau_c, std::vector<float>& out) {
  out.clear();
  const std::size_t P = d.shape.pixels();
  if (!(tau_c > 0) || d.shape.n < 2 || d.input_flow_dy.size() != d.shape.size()) return false;
  for (double te : d.exposure_s)
    if (!(te > 0)) return false;
  out.assign(d.shape.size(), 0.0f);
  std::vector<float> change(P);
  std::vector<double> carried(P, 0.0);
  bool any = false;
  for (int n = 0; n < d.shape.n; ++n) {
    const double period = n + 1 < d.shape.n ? d.t_s[n + 1] - d.t_s[n] : 0.0;
    const double te = d.exposure_s[n];
    if (period > 0) advance_along_flow(d, n, std::min(1.0, te / period), change.data());
    else std::fill(change.begin(), change.end(), 0.0f);
    // A shutter event leaves the pixels on the shutter: nothing of the change is carried over.
    const double c = n == 0 ? 0.0 : std::exp(-d.readout_s[n - 1] / tau_c);
    const double keep = n == 0 || d.flagged_event[n] ? 0.0 : c;
    float* o = out.data() + std::size_t(n) * P;
    for (std::size_t p = 0; p < P; ++p) {
      carried[p] = keep * carried[p] + (1 - c) * double(change[p]) / te;
      o[p] = static_cast<float>(carried[p]);
      any = any || o[p] != 0.0f;
    }
  }
  if (!any) out.clear();
  return any;
}

}  // namespace bolo::diag
