#include <algorithm>
#include <cstdint>

#include "bolo/diagnose/data.hpp"

namespace bolo::diag {

Blocks make_blocks(int frames, int folds_wanted) {
  Blocks b;
  // About four blocks per fold: long blocks keep slow noise (1/f) of a held-out block from being
  // predicted by its neighbours; at least two frames so lag-1 effects stay inside a block.
  b.folds = std::clamp(frames / 2, 1, folds_wanted);
  const int length = std::max(2, frames / std::max(1, b.folds * 4));
  b.count = std::max(1, (frames + length - 1) / length);
  b.folds = std::min(b.folds, b.count);
  b.block_of_frame.resize(frames);
  for (int n = 0; n < frames; ++n) b.block_of_frame[n] = std::min(n / length, b.count - 1);
  b.fold_of_block.resize(b.count);
  // Dealt in a fixed shuffled order: a round-robin deal would alias with periodic effects
  // (a repeat every 10 frames and 4 folds of 5-frame blocks leave whole folds without one).
  for (int k = 0; k < b.count; ++k) b.fold_of_block[k] = k % b.folds;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (int k = b.count - 1; k > 0; --k) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    std::swap(b.fold_of_block[k], b.fold_of_block[int((state >> 33) % std::uint64_t(k + 1))]);
  }
  return b;
}

Blocks halves(const Blocks& blocks) {
  Blocks h = blocks;
  h.folds = std::min(2, blocks.count);
  for (int k = 0; k < h.count; ++k) h.fold_of_block[k] = h.folds == 2 && 2 * k >= h.count ? 1 : 0;
  return h;
}

}  // namespace bolo::diag
