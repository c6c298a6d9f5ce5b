#pragma once
// Crosstalk's neighbourhood, shared by the simulator's blur and diagnose's regressors and nuisances.

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace bolo::effects {

// The mean of pixel (r, c)'s four neighbours in a w x h image, an edge's missing neighbour clamped
// to the frame (the pixel itself).
template <class T>
T mean_of_four_neighbours(const T* image, std::int64_t w, std::int64_t h, std::int64_t r, std::int64_t c) {
  const auto at = [&](std::int64_t row, std::int64_t col) {
    row = std::clamp<std::int64_t>(row, 0, h - 1);
    col = std::clamp<std::int64_t>(col, 0, w - 1);
    return image[static_cast<std::size_t>(row * w + col)];
  };
  return T(0.25) * (at(r - 1, c) + at(r + 1, c) + at(r, c - 1) + at(r, c + 1));
}

}  // namespace bolo::effects
