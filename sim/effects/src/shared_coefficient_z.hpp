#pragma once
// How far a coefficient that the whole recording shares stands out of its sampling error, for the
// candidates judged by a signature of their own (Candidate::signature_z): the residual regressed
// on K terms per pixel-frame, the first shared by every unit, the others each unit's own. A unit is
// the top or bottom half of the frame over a block of 10 frames; z is the shared coefficient against
// the units' spread, so a model error that the nuisance terms leave behind counts against it as far
// as it differs between units.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

struct UnitRows {
  int first, last;  // rows [first, last) of this unit
};

// Per unit, the shared coefficient's normal equation with the unit's own terms solved out.
struct UnitEstimates {
  std::vector<int> band;  // 0: the top half of the frame, 1: the bottom half
  std::vector<double> num, den;
};

// terms(n, y, c, p, rows, x) fills x (the shared term first) for frame n, pixel p = y * W + c, and
// returns false to leave the pixel-frame out; a term the recording lacks is left 0. Invalid and
// far-off pixels (far[p]) are left out.
template <int K, class Terms>
UnitEstimates unit_estimates(const DiagnoseData& d, const std::vector<float>& r, const std::vector<std::uint8_t>& far,
                             Terms terms) {
  using Vec = Eigen::Matrix<double, K, 1>;
  using Mat = Eigen::Matrix<double, K, K>;
  using Others = Eigen::Matrix<double, K - 1, K - 1>;
  const int N = d.shape.n, H = d.shape.height, W = d.shape.width;
  constexpr int kBlock = 10, kBands = 2;
  UnitEstimates out;
  for (int first = 0; first + kBlock <= N; first += kBlock)
    for (int band = 0; band < kBands; ++band) {
      const UnitRows rows{band * H / kBands, (band + 1) * H / kBands};
      Mat gram = Mat::Zero();
      Vec rhs = Vec::Zero();
      Vec x;
      for (int n = first; n < first + kBlock; ++n) {
        const float* f = d.frame(r, n);
        const std::uint8_t* v = d.valid_frame(n);
        for (int y = rows.first; y < rows.last; ++y)
          for (int c = 0; c < W; ++c) {
            const std::size_t p = std::size_t(y) * W + c;
            if (!v[p] || far[p] || !terms(n, y, c, p, rows, x)) continue;
            gram.template selfadjointView<Eigen::Lower>().rankUpdate(x);
            rhs += x * double(f[p]);
          }
      }
      gram = gram.template selfadjointView<Eigen::Lower>();
      if (!(gram(0, 0) > 0)) continue;
      // A term that is zero throughout the unit keeps a zero coefficient.
      Others others = gram.template bottomRightCorner<K - 1, K - 1>();
      for (int k = 0; k < K - 1; ++k)
        if (others(k, k) == 0) others(k, k) = 1;
      const Eigen::Matrix<double, K - 1, 1> cross = gram.template bottomLeftCorner<K - 1, 1>();
      const Eigen::Matrix<double, K - 1, 1> others_rhs = rhs.template tail<K - 1>();
      const Eigen::LDLT<Others> solve(others);
      if (solve.info() != Eigen::Success || !(others.determinant() > 0)) continue;
      out.band.push_back(band);
      out.num.push_back(rhs[0] - cross.dot(solve.solve(others_rhs)));
      out.den.push_back(gram(0, 0) - cross.dot(solve.solve(cross)));
    }
  return out;
}

// The shared coefficient over the units of `band` (-1: all) against their spread; NaN under 8
// units per band.
inline double shared_coefficient_z(const UnitEstimates& u, int band = -1) {
  constexpr std::size_t kMinUnitsPerBand = 8;
  double sn = 0, sd = 0;
  std::size_t B = 0;
  for (std::size_t b = 0; b < u.num.size(); ++b)
    if (band < 0 || u.band[b] == band) sn += u.num[b], sd += u.den[b], ++B;
  if (B < kMinUnitsPerBand * (band < 0 ? 2 : 1) || !(sd > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double slope = sn / sd;
  double spread = 0;
  for (std::size_t b = 0; b < u.num.size(); ++b)
    if (band < 0 || u.band[b] == band) {
      const double e = u.num[b] - slope * u.den[b];
      spread += e * e;
    }
  const double se = std::sqrt(spread * double(B) / double(B - 1)) / sd;
  return se > 0 ? slope / se : 0.0;
}

}  // namespace bolo::diag
