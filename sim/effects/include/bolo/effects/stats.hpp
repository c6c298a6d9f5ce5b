#pragma once
// Small robust statistics shared by the diagnosis sources.

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace bolo::diag {

template <typename T>
T median_in_place(std::vector<T>& v) {
  if (v.empty()) return T(0);
  auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

template <typename T>
T median_of(std::vector<T> v) { return median_in_place(v); }

// The baseline holds still at a pixel from one frame to the next: it changes by less than float
// rounding of its level (the test every "where the baseline holds still" selection uses).
inline bool holds_still(float b, float b_previous) {
  return std::fabs(b - b_previous) < 1e-3f + 1e-6f * std::fabs(b);
}

// A parameter value as the simulator's effect text takes it (six significant digits).
inline std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// Upper tail of the chi-square distribution (Wilson-Hilferty); enough for a reported p-value.
inline double chi2_sf(double x, double dof) {
  if (x <= 0) return 1.0;
  const double z = (std::cbrt(x / dof) - (1 - 2 / (9 * dof))) / std::sqrt(2 / (9 * dof));
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

}  // namespace bolo::diag
