#pragma once
// The per-pixel kernels behind the stages, one entry per implementation, for the tests that
// prove every SIMD path equal to the portable C++ definition. Not a stable API: stages call the
// dispatching functions (`correct_line`, `correct_line_update`, `nuc_line`).

#include <cstddef>
#include <cstdint>

#include "bolo/firmware/two_frame_corrector.hpp"

namespace bolo::fw::detail {

enum class KernelPath : std::uint8_t {
  portable,  // the C++ loop: the definition, and what ARM builds run
  avx2,      // x86-64 intrinsics, 16 pixels per step
  avx512,    // x86-64-v4 intrinsics (AVX-512 F/BW/VL/DQ), 32 pixels per step, masked tail
  avx512_vnni,  // the avx512 kernel with AVX512-VNNI multiply-accumulates (corrector only)
  neon,         // ARM NEON intrinsics (aarch64, armhf with NEON), 8 pixels per step; chosen at
                // build time, the only path besides portable on such builds
};
inline constexpr KernelPath kKernelPaths[] = {KernelPath::portable, KernelPath::avx2,
                                              KernelPath::avx512, KernelPath::avx512_vnni,
                                              KernelPath::neon};
const char* to_string(KernelPath path);

// Compiled into this build and supported by the CPU it runs on.
bool kernel_path_available(KernelPath path);
// The path `correct_line` / `correct_line_update` use on this CPU.
KernelPath selected_kernel_path();

using CorrectLineFn = void (*)(const Pixel* current, const Pixel* previous,
                               CorrectorCoefficients c, Pixel* out, std::size_t width,
                               std::uint32_t& low, std::uint32_t& high);
using CorrectUpdateFn = void (*)(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                                 Pixel* out, std::size_t width, std::uint32_t& low,
                                 std::uint32_t& high);
// nullptr where the path is not available.
CorrectLineFn correct_line_kernel(KernelPath path);
CorrectUpdateFn correct_update_kernel(KernelPath path);

// The NUC of one line (what nuc_line computes), per path: portable or NEON; nullptr elsewhere.
using NucLineFn = void (*)(const Pixel* in, const std::uint16_t* gain_q14,
                           const std::int16_t* offset, Pixel* out, std::size_t width);
NucLineFn nuc_line_kernel(KernelPath path);

// The bad-pixel stage's intake of one line: `in` into the ring line (through the NUC when
// `gain_q14` is set), each pixel flagged if the mask marks it (when `mask_bits` is set) or, with
// `detect_stuck`, its ring value is stuck_low or stuck_high. Flags are bits: pixel x is bit
// x % 32 of the 32-bit word at byte x / 32 * 4 of `flag_bits` (native byte order, unaligned;
// bits past the width are 0). `mask_bits` has the same layout (see pack_mask_bits).
struct IngestLine {
  const Pixel* in;
  const std::uint16_t* gain_q14;  // nullptr: no NUC
  const std::int16_t* offset;
  const std::uint8_t* mask_bits;  // nullptr: no mask
  bool detect_stuck;
  Pixel stuck_low, stuck_high;
  Pixel* ring;
  std::uint8_t* flag_bits;
  std::size_t width;
  // A hint, no change to the result: the input and tables come from beyond the L2 cache (large
  // frames), so the SIMD paths prefetch them ahead of use.
  bool prefetch = false;
};
// Returns whether any pixel was flagged.
using IngestFn = bool (*)(const IngestLine& job);
// Portable (the C++ loops, compiler-vectorised) or AVX-512; nullptr for a path not available or
// without its own version (AVX2 CPUs run the portable loops' AVX2 clone).
IngestFn ingest_kernel(KernelPath path);
// The best available one.
bool ingest_line(const IngestLine& job);

// `rows` (at most 64) consecutive lines of a frame in one call: line i is ingest_line of `first`
// with `in` advanced by i * in_stride, the tables and `ring` by i * width, and `flag_bits` and
// `mask_bits` by i * ceil(width / 32) * 4 bytes (ring lines and their flags back to back).
// Bit i of the result: line i has a flagged pixel.
using IngestRowsFn = std::uint64_t (*)(const IngestLine& first, std::size_t rows,
                                       std::size_t in_stride);
IngestRowsFn ingest_rows_kernel(KernelPath path);
std::uint64_t ingest_rows(const IngestLine& first, std::size_t rows, std::size_t in_stride);

// Bytes of one line's flag words (and of its mask bits): ceil(width / 32) 32-bit words.
constexpr std::size_t flag_line_bytes(std::size_t width) { return (width + 31) / 32 * 4; }
// A line of a byte mask (non-zero = bad) as bits in the flag-word layout, bits past the width 0:
// the bad-pixel stage packs its mask once at configuration, so the intake reads 1 bit a pixel
// instead of a byte.
void pack_mask_bits(const std::uint8_t* mask, std::size_t width, std::uint8_t* bits);

}  // namespace bolo::fw::detail
