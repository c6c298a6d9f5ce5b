#pragma once
// Synthetic but realistic input for bolo-bench: raw 14-bit microbolometer frames (a scene with a
// gradient and warm objects, fixed-pattern noise, temporal noise, a few stuck pixels) and the
// calibration the pipeline needs (NUC gain/offset tables, a bad-pixel mask). Deterministic: the
// same size always gives the same data.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bolo::bench {

struct BenchData {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  // `frames.size()` raw frames, each width * height, row-major, 14-bit values.
  std::vector<std::vector<std::uint16_t>> frames;
  std::vector<std::uint16_t> nuc_gain_q14;  // around unity (16384), +-3 %
  std::vector<std::int16_t> nuc_offset;     // +-60 counts
  std::vector<std::uint8_t> bad_mask;       // ~0.1 % of pixels flagged
};

// `count` distinct frames of one scene whose temporal noise differs frame to frame.
BenchData make_bench_data(std::uint32_t width, std::uint32_t height, std::size_t count);

}  // namespace bolo::bench
