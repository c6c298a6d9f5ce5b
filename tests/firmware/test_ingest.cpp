// Every compiled-in path of the bad-pixel stage's line intake (copy or NUC into the ring, flags)
// against the portable loops: ring, flag bits, the "any flagged" answer, no write outside the line.

#include <catch2/catch.hpp>

#include <cstdio>
#include <cstring>
#include <vector>

#include "bolo/firmware/detail/kernels.hpp"
#include "frame_collector.hpp"

using namespace bolo;
using bolo::test::SplitMix64;
using fw::detail::KernelPath;

namespace {

constexpr std::size_t kGuard = 40;
constexpr fw::Pixel kSentinel = 0xA5A5;
constexpr std::uint8_t kFlagSentinel = 0x5A;

struct Outcome {
  std::vector<fw::Pixel> ring;
  std::vector<std::uint8_t> flags;  // the flag words' bytes, with guards
  bool any = false;
};

Outcome run(KernelPath path, fw::detail::IngestLine job) {
  Outcome o;
  o.ring.assign(job.width + 2 * kGuard, kSentinel);
  o.flags.assign((job.width + 31) / 32 * 4 + 2 * kGuard, kFlagSentinel);
  job.ring = o.ring.data() + kGuard;
  job.flag_bits = o.flags.data() + kGuard;
  const auto kernel = fw::detail::ingest_kernel(path);
  REQUIRE(kernel != nullptr);
  o.any = kernel(job);
  return o;
}

// A byte mask (non-zero = bad) of `rows` lines of `width` as the intake's mask bits, lines back
// to back like flag words.
std::vector<std::uint8_t> mask_bits_of(const std::uint8_t* mask, std::size_t width,
                                       std::size_t rows = 1) {
  const std::size_t line = fw::detail::flag_line_bytes(width);
  std::vector<std::uint8_t> bits(rows * line + 4);  // + 4: a pointer to it is never past the end
  for (std::size_t i = 0; i < rows; ++i)
    fw::detail::pack_mask_bits(mask + i * width, width, bits.data() + i * line);
  return bits;
}

}  // namespace

TEST_CASE("pack_mask_bits puts pixel x at bit x % 32 of word x / 32", "[kernels][bad_pixel]") {
  std::vector<std::uint8_t> mask(70, 0);
  mask[0] = 1;
  mask[5] = 255;
  mask[31] = 2;
  mask[32] = 1;
  mask[69] = 1;
  const std::vector<std::uint8_t> bits = mask_bits_of(mask.data(), mask.size());
  std::uint32_t w[3];
  std::memcpy(w, bits.data(), sizeof w);
  CHECK(w[0] == 0x80000021u);
  CHECK(w[1] == 0x00000001u);
  CHECK(w[2] == 0x00000020u);  // bits past the width stay 0
}

TEST_CASE("every ingest path equals the portable loops", "[kernels][bad_pixel]") {
  std::vector<KernelPath> paths;
  for (KernelPath p : fw::detail::kKernelPaths) {
    if (p != KernelPath::portable && fw::detail::ingest_kernel(p) != nullptr) paths.push_back(p);
  }
  if (paths.empty()) std::printf("ingest: only the portable path on this build/CPU\n");
  const std::vector<fw::Pixel> edges = {0, 1, 2, 0x3FFE, 0x3FFF, 0x4000, 32767, 32768, 65534, 65535};
  SplitMix64 rng(41);
  for (std::size_t width : {0, 1, 2, 15, 16, 17, 31, 32, 33, 63, 64, 65, 160, 640, 1317}) {
    for (std::size_t offset : {0, 1, 7}) {
      const std::size_t n = offset + width;
      std::vector<fw::Pixel> in(n);
      std::vector<std::uint16_t> gain(n);
      std::vector<std::int16_t> off(n);
      std::vector<std::uint8_t> mask(n);
      for (int round = 0; round < 16; ++round) {
        for (std::size_t i = 0; i < n; ++i) {
          const std::uint32_t roll = rng.below(8);
          in[i] = roll == 0 ? edges[rng.below(static_cast<std::uint32_t>(edges.size()))]
                            : static_cast<fw::Pixel>(round % 2 ? rng.next() : rng.next() & 0x3FFF);
          gain[i] = rng.below(3) == 0 ? static_cast<std::uint16_t>(rng.next())
                                      : static_cast<std::uint16_t>(16384 - 64 + rng.below(128));
          if (rng.below(16) == 0) gain[i] = static_cast<std::uint16_t>(rng.below(2) ? 0xFFFF : 0);
          off[i] = rng.below(3) == 0 ? static_cast<std::int16_t>(rng.next())
                                     : static_cast<std::int16_t>(static_cast<int>(rng.below(7)) - 3);
          mask[i] = rng.below(10) == 0 ? static_cast<std::uint8_t>(1 + rng.below(255)) : 0;
        }
        const bool nuc = round % 4 < 2;
        const std::vector<std::uint8_t> mask_bits = mask_bits_of(mask.data() + offset, width);
        fw::detail::IngestLine job{in.data() + offset,
                                   nuc ? gain.data() + offset : nullptr,
                                   nuc ? off.data() + offset : nullptr,
                                   round % 3 != 0 ? mask_bits.data() : nullptr,
                                   round % 5 != 4,
                                   static_cast<fw::Pixel>(rng.below(3)),
                                   static_cast<fw::Pixel>(round % 2 ? 0x3FFF : 65535 - rng.below(2)),
                                   nullptr,
                                   nullptr,
                                   width};
        const Outcome want = run(KernelPath::portable, job);
        for (KernelPath path : paths) {
          INFO("path " << fw::detail::to_string(path) << " width " << width << " offset " << offset
                       << " round " << round);
          const Outcome got = run(path, job);
          CHECK(got.ring == want.ring);  // includes the guards: nothing written outside
          CHECK(got.flags == want.flags);
          CHECK(got.any == want.any);
        }
      }
    }
  }
}

TEST_CASE("the portable ingest loops follow their definition", "[kernels][bad_pixel]") {
  const std::vector<fw::Pixel> in = {0, 5, 0x3FFF, 100, 200, 65535};
  const std::vector<std::uint16_t> gain = {16384, 32768, 16384, 16384, 8192, 16384};
  const std::vector<std::int16_t> off = {0, 0, 0, -100, 1, 0};
  const std::vector<std::uint8_t> mask = {0, 0, 0, 0, 7, 0};
  const std::vector<std::uint8_t> mask_bits = mask_bits_of(mask.data(), mask.size());
  std::vector<fw::Pixel> ring(in.size());
  std::uint32_t flags = 0xFFFFFFFFu;
  fw::detail::IngestLine job{in.data(), gain.data(), off.data(), mask_bits.data(), true, 0, 0x3FFF,
                             ring.data(), reinterpret_cast<std::uint8_t*>(&flags), in.size()};
  CHECK(fw::detail::ingest_kernel(KernelPath::portable)(job));
  CHECK(ring == std::vector<fw::Pixel>{0, 10, 0x3FFF, 0, 101, 65535});
  CHECK(flags == 0b011101u);  // pixel x is bit x; bits past the width are 0
  job.mask_bits = nullptr;
  job.detect_stuck = false;
  CHECK_FALSE(fw::detail::ingest_kernel(KernelPath::portable)(job));
  CHECK(flags == 0u);
}

// The AVX-512 intake computes the NUC in 16-bit lanes when every pixel of a 32-pixel step is
// below 2^14 and every gain below 2^15 (the usual case), and in 32-bit lanes otherwise. The test
// above mostly draws steps of the general case; this one keeps to the 16-bit range (every pixel
// value there against edge gains and offsets, then random lines) and puts single pixels or
// gains just outside it into some steps.
TEST_CASE("every ingest path equals the portable loops in and around the 16-bit NUC range",
          "[kernels][bad_pixel]") {
  std::vector<KernelPath> paths;
  for (KernelPath p : fw::detail::kKernelPaths) {
    if (p != KernelPath::portable && fw::detail::ingest_kernel(p) != nullptr) paths.push_back(p);
  }
  const auto compare = [&](const fw::detail::IngestLine& job) {
    const Outcome want = run(KernelPath::portable, job);
    for (KernelPath path : paths) {
      INFO("path " << fw::detail::to_string(path) << " width " << job.width);
      const Outcome got = run(path, job);
      CHECK(got.ring == want.ring);
      CHECK(got.flags == want.flags);
      CHECK(got.any == want.any);
    }
  };
  {  // every pixel value below 2^14, each edge gain with each edge offset
    constexpr std::size_t kWidth = 16384;
    std::vector<fw::Pixel> in(kWidth);
    for (std::size_t i = 0; i < kWidth; ++i) in[i] = static_cast<fw::Pixel>(i);
    for (std::uint16_t g : {0, 1, 8191, 16383, 16384, 16385, 24576, 32766, 32767}) {
      for (std::int16_t o : {-32768, -32767, -16384, -1, 0, 1, 16383, 32767}) {
        const std::vector<std::uint16_t> gain(kWidth, g);
        const std::vector<std::int16_t> off(kWidth, o);
        INFO("gain " << g << " offset " << o);
        compare({in.data(), gain.data(), off.data(), nullptr, true, 0, 0x3FFF, nullptr, nullptr,
                 kWidth});
      }
    }
  }
  SplitMix64 rng(43);
  const std::vector<fw::Pixel> outside_in = {0x4000, 0x7FFF, 0x8000, 0xC000, 0xFFFF};
  const std::vector<std::uint16_t> outside_gain = {0x8000, 0x8001, 0xFFFF};
  for (std::size_t width : {1, 31, 32, 33, 64, 97, 160, 640}) {
    std::vector<fw::Pixel> in(width);
    std::vector<std::uint16_t> gain(width);
    std::vector<std::int16_t> off(width);
    std::vector<std::uint8_t> mask(width);
    for (int round = 0; round < 64; ++round) {
      for (std::size_t i = 0; i < width; ++i) {
        in[i] = static_cast<fw::Pixel>(rng.below(8) == 0 ? (rng.below(2) ? 0 : 0x3FFF)
                                                         : rng.below(0x4000));
        gain[i] = static_cast<std::uint16_t>(rng.below(4) == 0 ? rng.below(0x8000)
                                                               : 16384 - 512 + rng.below(1024));
        off[i] = static_cast<std::int16_t>(rng.below(4) == 0 ? static_cast<int>(rng.next() & 0xFFFF) - 32768
                                                             : static_cast<int>(rng.below(201)) - 100);
        mask[i] = rng.below(50) == 0 ? 1 : 0;
      }
      if (round % 4 == 1) in[rng.below(static_cast<std::uint32_t>(width))] =
          outside_in[rng.below(static_cast<std::uint32_t>(outside_in.size()))];
      if (round % 4 == 3) gain[rng.below(static_cast<std::uint32_t>(width))] =
          outside_gain[rng.below(static_cast<std::uint32_t>(outside_gain.size()))];
      const std::vector<std::uint8_t> mask_bits = mask_bits_of(mask.data(), width);
      compare({in.data(), gain.data(), off.data(), round % 2 ? mask_bits.data() : nullptr, true, 0,
               0x3FFF, nullptr, nullptr, width});
    }
  }
}

// ingest_rows: `rows` lines in one call, each exactly as ingest_line would take it, with the ring
// lines and flag words back to back and bit i of the answer for line i.
TEST_CASE("every ingest_rows path equals line-by-line ingest", "[kernels][bad_pixel]") {
  SplitMix64 rng(47);
  for (KernelPath path : fw::detail::kKernelPaths) {
    const auto rows_kernel = fw::detail::ingest_rows_kernel(path);
    if (rows_kernel == nullptr) continue;
    for (std::size_t width : {1, 31, 32, 33, 160, 161, 1317}) {
      for (std::size_t rows : {1, 2, 5, 64}) {
        const std::size_t stride = width + rng.below(3);
        const std::size_t n = rows * width;
        std::vector<fw::Pixel> in(rows * stride);
        std::vector<std::uint16_t> gain(n);
        std::vector<std::int16_t> off(n);
        std::vector<std::uint8_t> mask(n);
        for (auto& v : in) v = static_cast<fw::Pixel>(rng.below(8) == 0 ? rng.next() : rng.below(0x4000));
        for (auto& g : gain) g = static_cast<std::uint16_t>(16384 - 256 + rng.below(512));
        for (auto& o : off) o = static_cast<std::int16_t>(static_cast<int>(rng.below(41)) - 20);
        // about one flagged line in three
        for (auto& m : mask) m = rng.below(static_cast<std::uint32_t>(3 * width)) == 0 ? 1 : 0;
        const std::vector<std::uint8_t> mask_bits = mask_bits_of(mask.data(), width, rows);
        for (int variant = 0; variant < 8; ++variant) {  // 4..7: the same with the prefetch hint
          const bool nuc = variant % 2 == 0;
          const bool with_mask = variant % 4 < 2;
          const std::size_t flag_bytes = (width + 31) / 32 * 4;
          std::vector<fw::Pixel> ring(n + 2 * kGuard, kSentinel);
          std::vector<std::uint8_t> flags(rows * flag_bytes + 2 * kGuard, kFlagSentinel);
          const fw::detail::IngestLine first{in.data(), nuc ? gain.data() : nullptr,
                                             nuc ? off.data() : nullptr,
                                             with_mask ? mask_bits.data() : nullptr, true, 0, 0x3FFF,
                                             ring.data() + kGuard, flags.data() + kGuard, width,
                                             variant >= 4};
          INFO("path " << fw::detail::to_string(path) << " width " << width << " rows " << rows
                       << " variant " << variant);
          const std::uint64_t got = rows_kernel(first, rows, stride);
          std::vector<fw::Pixel> want_ring(n + 2 * kGuard, kSentinel);
          std::vector<std::uint8_t> want_flags(rows * flag_bytes + 2 * kGuard, kFlagSentinel);
          std::uint64_t want = 0;
          for (std::size_t i = 0; i < rows; ++i) {
            fw::detail::IngestLine line = first;
            line.in = in.data() + i * stride;
            if (nuc) {
              line.gain_q14 = gain.data() + i * width;
              line.offset = off.data() + i * width;
            }
            if (with_mask) line.mask_bits = mask_bits.data() + i * flag_bytes;
            line.prefetch = false;
            line.ring = want_ring.data() + kGuard + i * width;
            line.flag_bits = want_flags.data() + kGuard + i * flag_bytes;
            if (fw::detail::ingest_kernel(KernelPath::portable)(line)) want |= std::uint64_t{1} << i;
          }
          CHECK(got == want);
          CHECK(ring == want_ring);
          CHECK(flags == want_flags);
        }
      }
    }
  }
}
