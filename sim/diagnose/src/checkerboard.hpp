#pragma once
// The 2x2 checkerboard difference both noise figures of diagnose read.

#include <cstddef>

namespace bolo::diag {

// Half the second difference of the 2x2 block whose top-left pixel is p, in an image w pixels
// wide: (v00 - v01 - v10 + v11) / 2. White noise keeps its variance; anything constant along rows
// or along columns, or linear over the block, cancels.
inline float checkerboard_difference(const float* v, std::size_t p, std::size_t w) {
  return 0.5f * (v[p] - v[p + 1] - v[p + w] + v[p + w + 1]);
}

}  // namespace bolo::diag
