#pragma once
// --nuc FILE: the per-pixel non-uniformity correction the firmware applies before everything else
// (NucStage: out = saturate_u16(round(in * gain) + offset)), read from a NumPy .npy of float32,
// shape (2, H, W): [0] each pixel's gain, [1] its offset in counts. Held in the firmware's units:
// Q2.14 gain (0 .. 65535/16384), int16 offset.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "bolo/firmware/nuc_stage.hpp"

namespace bolo::correct {

struct NucFile {
  std::vector<std::uint16_t> gain_q14;
  std::vector<std::int16_t> offset;
  fw::NucTables tables() const { return {gain_q14, offset}; }
};

// Throws Error naming --nuc, the file and the first pixel at fault: a file that is not a float32
// .npy, a shape other than (2, height, width), a gain outside the Q2.14 range, an offset outside
// int16, a value that is not finite.
NucFile read_nuc_file(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height);

}  // namespace bolo::correct
