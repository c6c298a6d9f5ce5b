// Block-matching flow of the simulation input (scene_flow.hpp).

#include "bolo/effects/scene_flow.hpp"

#include "bolo/diagnose/frame_start.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

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

// An image with its border replicated `pad` pixels outward: reads within the pad equal
// Image::at's clamped ones, without the clamps in the matching's inner loops.
struct PaddedImage {
  int pad = 0, stride = 0;
  std::vector<float> v;
  void fill(const Image& im, int border) {
    pad = border;
    stride = im.w + 2 * pad;
    v.resize(std::size_t(im.h + 2 * pad) * stride);
    for (int r = -pad; r < im.h + pad; ++r)
      for (int c = -pad; c < im.w + pad; ++c) v[std::size_t(r + pad) * stride + (c + pad)] = im.at(r, c);
  }
  const float* at(int r, int c) const { return v.data() + std::ptrdiff_t(r + pad) * stride + (c + pad); }
};

// Sum of squared differences of next(x) against now(x - d) over the window about (r, c), row by
// row (the order every matching sum here keeps). Needs pad >= radius + max(|dy|, |dx|).
double window_ssd(const PaddedImage& now, const PaddedImage& next, int r, int c, int dy, int dx, int radius) {
  double s = 0;
  for (int i = -radius; i <= radius; ++i) {
    const float *nx = next.at(r + i, c), *nw = now.at(r + i - dy, c - dx);
    for (int j = -radius; j <= radius; ++j) {
      const double e = double(nx[j]) - nw[j];
      s += e * e;
    }
  }
  return s;
}

// window_ssd for the nine displacements (cy + a, cx + b), a, b in -1..1, row by row in `out`;
// each sum in window_ssd's order (so equal to it), the nine interleaved. Needs
// pad >= radius + max(|cy|, |cx|) + 1.
static_assert(kFineReach == 1, "the fine search's nine displacements are window_ssd_3x3's");
void window_ssd_3x3(const PaddedImage& now, const PaddedImage& next, int r, int c, int cy, int cx, int radius,
                    double out[9]) {
  for (int k = 0; k < 9; ++k) out[k] = 0;
  for (int i = -radius; i <= radius; ++i) {
    const float* nx = next.at(r + i, c);
    const float* nw = now.at(r + i - cy, c - cx);
    for (int j = -radius; j <= radius; ++j) {
      const double y = nx[j];
      for (int a = -1; a <= 1; ++a) {
        const float* row = nw - std::ptrdiff_t(a) * now.stride + j;
        for (int b = -1; b <= 1; ++b) {
          const double e = y - row[-b];
          out[(a + 1) * 3 + (b + 1)] += e * e;
        }
      }
    }
  }
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

// The coarse search at every `wanted` pixel over displacements up to `reach`, offered to best[]
// (reset here) in the order of a per-pixel search (dy, then dx, ascending). One displacement at a
// time: its squared differences once per pixel, then each window's sum in window_ssd's order (so
// equal to it), whole rows at once. Needs pad >= kCoarseRadius + reach.
void coarse_match(const PaddedImage& now, const PaddedImage& next, int h, int w, int reach,
                  const std::vector<std::uint8_t>& wanted, std::vector<Best>& best) {
  constexpr int R = kCoarseRadius;
  const int dw = w + 2 * R;
  best.assign(std::size_t(h) * w, Best{});
  std::vector<char> row_wanted(h, 0);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) row_wanted[r] = row_wanted[r] || wanted[std::size_t(r) * w + c];
  std::vector<double> squares(std::size_t(h + 2 * R) * dw), sums(w);
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx) {
      for (int r = -R; r < h + R; ++r) {
        const float *nx = next.at(r, -R), *nw = now.at(r - dy, -R - dx);
        double* out = squares.data() + std::size_t(r + R) * dw;
        for (int c = 0; c < dw; ++c) {
          const double e = double(nx[c]) - nw[c];
          out[c] = e * e;
        }
      }
      for (int r = 0; r < h; ++r) {
        if (!row_wanted[r]) continue;
        double* s = sums.data();
        std::fill(sums.begin(), sums.end(), 0.0);
        for (int i = -R; i <= R; ++i)
          for (int j = -R; j <= R; ++j) {
            const double* q = squares.data() + std::size_t(r + i + R) * dw + (j + R);
            for (int c = 0; c < w; ++c) s[c] += q[c];
          }
        for (int c = 0; c < w; ++c)
          if (wanted[std::size_t(r) * w + c]) best[std::size_t(r) * w + c].offer(s[c], dy, dx);
      }
    }
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
  const int h2 = H / 2, w2 = W / 2;
  std::vector<std::uint8_t> wanted(std::size_t(h2) * w2);
  std::vector<Best> coarse;
  PaddedImage coarse_now, coarse_next, fine_now, fine_next;
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
    std::fill(wanted.begin(), wanted.end(), 0);
    for (int r = 0; r < h2; ++r)
      for (int c = 0; c < w2; ++c) {
        const std::size_t q = std::size_t(2 * r) * W + 2 * c;
        wanted[std::size_t(r) * w2 + c] = near_change[q] || near_change[q + 1] || near_change[q + W] || near_change[q + W + 1];
      }
    coarse_now.fill(Image{h2, w2, now2.data()}, kCoarseRadius + coarse_reach);
    coarse_next.fill(Image{h2, w2, next2.data()}, kCoarseRadius + coarse_reach);
    coarse_match(coarse_now, coarse_next, h2, w2, coarse_reach, wanted, coarse);
    const int fine_pad = kFineRadius + 2 * coarse_reach + kFineReach;
    fine_now.fill(Image{H, W, a}, fine_pad);
    fine_next.fill(Image{H, W, b}, fine_pad);
    std::int8_t* fy = d.input_flow_dy.data() + std::size_t(n) * P;
    std::int8_t* fx = d.input_flow_dx.data() + std::size_t(n) * P;
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c) {
        if (!near_change[std::size_t(r) * W + c]) continue;
        const std::size_t q = std::size_t(std::min(r / 2, h2 - 1)) * w2 + std::min(c / 2, w2 - 1);
        const int cy = 2 * coarse[q].dy, cx = 2 * coarse[q].dx;
        Best best;
        best.offer(window_ssd(fine_now, fine_next, r, c, 0, 0, kFineRadius), 0, 0);
        double costs[9];
        window_ssd_3x3(fine_now, fine_next, r, c, cy, cx, kFineRadius, costs);
        for (int dy = cy - kFineReach; dy <= cy + kFineReach; ++dy)
          for (int dx = cx - kFineReach; dx <= cx + kFineReach; ++dx)
            if (std::abs(dy) <= 127 && std::abs(dx) <= 127 && (dy != 0 || dx != 0))
              best.offer(costs[(dy - cy + 1) * 3 + (dx - cx + 1)], dy, dx);
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
  const std::int8_t* fy = d.input_flow_dy.data() + std::size_t(n) * P;
  const std::int8_t* fx = d.input_flow_dx.data() + std::size_t(n) * P;
  int reach = 0;
  for (std::size_t p = 0; p < P; ++p) reach = std::max({reach, std::abs(int(fy[p])), std::abs(int(fx[p]))});
  PaddedImage now, next;
  now.fill(Image{H, W, a}, kFineRadius + reach + 1);
  next.fill(Image{H, W, b}, kFineRadius + reach + 1);
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
      double cost[9];  // at (y + a, x + b), a, b in -1..1
      window_ssd_3x3(now, next, r, c, y, x, kFineRadius, cost);
      const double centre = cost[4];
      dy[p] = static_cast<float>(y + vertex(cost[1], centre, cost[7]));
      dx[p] = static_cast<float>(x + vertex(cost[3], centre, cost[5]));
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
    const double keep = restarts(d, n) ? 0.0 : c;
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
