// Every compiled-in SIMD path of the corrector kernel against the portable loop (the
// definition): outputs, saturation counts and the frame-store update, on edge values, exhaustive
// sweeps and random data, at every width of a step and its tail and at unaligned addresses.
// Paths the CPU lacks are skipped (and reported); on ARM only the portable path exists.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "bolo/firmware/detail/kernels.hpp"
#include "bolo/firmware/nuc_stage.hpp"
#include "frame_collector.hpp"

using namespace bolo;
using bolo::test::SplitMix64;
using fw::detail::KernelPath;

namespace {

const std::vector<fw::Pixel> kEdgePixels = {0,     1,     2,     3,     127,   128,   255,
                                            256,   8191,  8192,  16382, 16383, 16384, 32767,
                                            32768, 32769, 49151, 65533, 65534, 65535};

std::vector<fw::CorrectorCoefficients> coefficient_sets(SplitMix64& rng) {
  std::vector<fw::CorrectorCoefficients> sets = {
      {1u << 24, 0},
      {1u << 24, 1u << 24},
      {0, 0},
      {0, 0xFFFFFFFFu},
      {0xFFFFFFFFu, 0},
      {0xFFFFFFFFu, 0xFFFFFFFFu},
      {0xFFFFFFFFu, 1},
      {1, 0xFFFFFFFFu},
      {1u << 25, 0},             // 2.0: cur >= 32768 saturates high
      {1u << 25, 1u << 24},      // 2 cur - prev
      {(1u << 24) + (1u << 23), 1u << 23},  // ties: 1.5 cur - 0.5 prev
      {(1u << 24) + 1, (1u << 24) - 1},
      {0x80000000u, 0x7FFFFFFFu},
      {0x7FFFFFFFu, 0x80000000u},  // A > G: never produced by the coefficients, still defined
      {28'065'735, 16'813'222},    // bench timing (g ~ 1.67, a ~ 0.60)
  };
  for (int i = 0; i < 40; ++i) {
    const auto g = static_cast<std::uint32_t>(rng.next());
    sets.push_back({g, static_cast<std::uint32_t>(rng.next() % (std::uint64_t{g} + 1))});
    sets.push_back({static_cast<std::uint32_t>(rng.next()), static_cast<std::uint32_t>(rng.next())});
    // realistic: g in [1, 8), A <= G
    const std::uint32_t g2 = (1u << 24) + static_cast<std::uint32_t>(rng.next() % (7u << 24));
    sets.push_back({g2, static_cast<std::uint32_t>(rng.next() % (std::uint64_t{g2} + 1))});
  }
  return sets;
}

struct Result {
  std::vector<fw::Pixel> out;
  std::vector<fw::Pixel> store;  // the previous line after correct_update
  std::uint32_t low = 0, high = 0;
};

// Runs one path on [offset, offset + width) of the inputs; both variants (plain and fused store
// update) must agree with each other, and the fused one must leave `current` in the store.
Result run(KernelPath path, const std::vector<fw::Pixel>& cur, const std::vector<fw::Pixel>& prev,
           fw::CorrectorCoefficients c, std::size_t offset, std::size_t width) {
  const auto correct = fw::detail::correct_line_kernel(path);
  const auto update = fw::detail::correct_update_kernel(path);
  REQUIRE(correct != nullptr);
  REQUIRE(update != nullptr);
  // Sentinels around the output show a write past the end.
  constexpr fw::Pixel kSentinel = 0xA5A5;
  Result r;
  std::vector<fw::Pixel> out(width + 2 * 40, kSentinel);
  correct(cur.data() + offset, prev.data() + offset, c, out.data() + 40, width, r.low, r.high);
  std::vector<fw::Pixel> store(width + 2 * 40, kSentinel);
  std::copy(prev.begin() + static_cast<std::ptrdiff_t>(offset),
            prev.begin() + static_cast<std::ptrdiff_t>(offset + width), store.begin() + 40);
  std::vector<fw::Pixel> out2(width + 2 * 40, kSentinel);
  std::uint32_t low2 = 0, high2 = 0;
  update(cur.data() + offset, store.data() + 40, c, out2.data() + 40, width, low2, high2);
  CHECK(out2 == out);
  CHECK(low2 == r.low);
  CHECK(high2 == r.high);
  for (std::size_t i = 0; i < 40; ++i) {
    CHECK(out[i] == kSentinel);
    CHECK(out[40 + width + i] == kSentinel);
    CHECK(store[i] == kSentinel);
    CHECK(store[40 + width + i] == kSentinel);
  }
  CHECK(std::equal(store.begin() + 40, store.begin() + 40 + static_cast<std::ptrdiff_t>(width),
                   cur.begin() + static_cast<std::ptrdiff_t>(offset)));
  r.out.assign(out.begin() + 40, out.begin() + 40 + static_cast<std::ptrdiff_t>(width));
  return r;
}

// Compares `path` against the portable loop on the whole of cur/prev for every coefficient set.
std::size_t compare(KernelPath path, const std::vector<fw::Pixel>& cur,
                    const std::vector<fw::Pixel>& prev,
                    const std::vector<fw::CorrectorCoefficients>& sets, std::size_t offset = 0) {
  std::size_t differing = 0;
  const std::size_t width = cur.size() - offset;
  for (const auto& c : sets) {
    const Result want = run(KernelPath::portable, cur, prev, c, offset, width);
    const Result got = run(path, cur, prev, c, offset, width);
    if (got.out != want.out || got.low != want.low || got.high != want.high) ++differing;
  }
  return differing;
}

std::vector<KernelPath> paths_to_test() {
  std::vector<KernelPath> paths;
  for (KernelPath p : fw::detail::kKernelPaths) {
    if (fw::detail::kernel_path_available(p)) {
      paths.push_back(p);
    } else {
      std::printf("kernel path %s: not available on this build/CPU, skipped\n",
                  fw::detail::to_string(p));
    }
  }
  return paths;
}

}  // namespace

TEST_CASE("the selected kernel path is available and the portable path always is", "[kernels]") {
  CHECK(fw::detail::kernel_path_available(KernelPath::portable));
  CHECK(fw::detail::kernel_path_available(fw::detail::selected_kernel_path()));
}

TEST_CASE("every kernel path equals the portable loop on all pairs of edge values", "[kernels]") {
  SplitMix64 rng(7);
  const auto sets = coefficient_sets(rng);
  std::vector<fw::Pixel> cur, prev;
  for (fw::Pixel a : kEdgePixels)
    for (fw::Pixel b : kEdgePixels) {
      cur.push_back(a);
      prev.push_back(b);
    }
  for (KernelPath path : paths_to_test()) {
    INFO("path " << fw::detail::to_string(path));
    CHECK(compare(path, cur, prev, sets) == 0);
    CHECK(compare(path, cur, prev, sets, 1) == 0);  // every pixel moves to another lane
    CHECK(compare(path, cur, prev, sets, 3) == 0);
  }
}

TEST_CASE("every kernel path equals the portable loop for every u16 current value", "[kernels]") {
  // All 65536 current values against edge and random predecessors, for a spread of coefficients.
  SplitMix64 rng(11);
  std::vector<fw::CorrectorCoefficients> sets = coefficient_sets(rng);
  sets.resize(24);
  std::vector<fw::Pixel> cur(65536);
  for (std::size_t i = 0; i < cur.size(); ++i) cur[i] = static_cast<fw::Pixel>(i);
  const auto paths = paths_to_test();
  for (int round = 0; round < 6; ++round) {
    std::vector<fw::Pixel> prev(cur.size());
    for (auto& p : prev)
      p = round < 3 ? kEdgePixels[rng.below(static_cast<std::uint32_t>(kEdgePixels.size()))]
                    : static_cast<fw::Pixel>(rng.next());
    for (KernelPath path : paths) {
      INFO("path " << fw::detail::to_string(path) << ", round " << round);
      CHECK(compare(path, cur, prev, sets) == 0);
    }
  }
}

TEST_CASE("every kernel path equals the portable loop at every width and alignment", "[kernels]") {
  SplitMix64 rng(13);
  auto sets = coefficient_sets(rng);
  sets.resize(20);
  const auto paths = paths_to_test();
  for (std::size_t width : {0, 1, 2, 7, 8, 15, 16, 17, 31, 32, 33, 47, 48, 63, 64, 65, 95, 96, 97,
                            127, 128, 129, 160, 640, 1280, 1317}) {
    for (std::size_t offset : {0, 1, 5, 8, 16}) {
      std::vector<fw::Pixel> cur(offset + width), prev(offset + width);
      for (std::size_t i = 0; i < cur.size(); ++i) {
        const bool wide = rng.below(4) == 0;  // mostly 14-bit, some full range
        cur[i] = static_cast<fw::Pixel>(wide ? rng.next() : rng.next() & 0x3FFF);
        prev[i] = static_cast<fw::Pixel>(wide ? rng.next() : rng.next() & 0x3FFF);
      }
      for (KernelPath path : paths) {
        INFO("path " << fw::detail::to_string(path) << ", width " << width << ", offset "
                     << offset);
        CHECK(compare(path, cur, prev, sets, offset) == 0);
      }
    }
  }
}

TEST_CASE("every kernel path counts saturation like the portable loop", "[kernels]") {
  // Lines built to sit on the clamping boundaries: value -1, 0, 65535, 65536 and ties around them.
  const fw::CorrectorCoefficients unity{1u << 24, 1u << 24};  // out = cur - prev
  const fw::CorrectorCoefficients twice{1u << 25, 1u << 24};  // out = 2 cur - prev
  std::vector<fw::Pixel> cur, prev;
  for (fw::Pixel a : kEdgePixels)
    for (int d = -2; d <= 2; ++d) {
      cur.push_back(a);
      prev.push_back(static_cast<fw::Pixel>(std::clamp(int{a} + d, 0, 65535)));
      cur.push_back(static_cast<fw::Pixel>(32767 + (d + 2) % 3));
      prev.push_back(static_cast<fw::Pixel>(std::clamp(d, 0, 65535)));
    }
  for (KernelPath path : paths_to_test()) {
    INFO("path " << fw::detail::to_string(path));
    const Result want_u = run(KernelPath::portable, cur, prev, unity, 0, cur.size());
    const Result want_t = run(KernelPath::portable, cur, prev, twice, 0, cur.size());
    CHECK(want_u.low > 0);
    CHECK(want_t.high > 0);
    const Result got_u = run(path, cur, prev, unity, 0, cur.size());
    const Result got_t = run(path, cur, prev, twice, 0, cur.size());
    CHECK(got_u.out == want_u.out);
    CHECK(got_u.low == want_u.low);
    CHECK(got_u.high == want_u.high);
    CHECK(got_t.out == want_t.out);
    CHECK(got_t.low == want_t.low);
    CHECK(got_t.high == want_t.high);
  }
}

// The AVX-512 VNNI kernel takes blocks of 128 pixels whose inputs are all below 2^15 (14-bit
// data) without the bit flip and tests them for out-of-range values once per block; a block that
// fails either test is redone the general way. Long lines of such inputs, some blocks with a
// saturating pixel (low or high) or one input at or above 2^15, at several offsets and every
// coefficient set: outputs, counts and the store update as the portable loop's.
TEST_CASE("every kernel path equals the portable loop on long lines below 2^15, saturation included",
          "[kernels]") {
  SplitMix64 rng(53);
  std::vector<fw::CorrectorCoefficients> sets = coefficient_sets(rng);
  sets.push_back({3u << 24, 1u << 24});               // 3 cur - prev: high above cur 21845
  sets.push_back({(1u << 28) + 5, (1u << 28) - 7});  // G, A >= 2^28: the third digit
  for (KernelPath path : paths_to_test()) {
    for (std::size_t width : {128, 255, 512, 1000}) {
      for (std::size_t offset : {0, 3}) {
        std::vector<fw::Pixel> cur(offset + width), prev(offset + width);
        for (std::size_t i = 0; i < cur.size(); ++i) {
          cur[i] = static_cast<fw::Pixel>(4000 + rng.below(200));
          prev[i] = static_cast<fw::Pixel>(cur[i] + rng.below(40) - 20);
        }
        // about every third block: a pixel far below its predecessor (negative with unity
        // coefficients), a bright one (high with 3 cur - prev), or an input at 2^15 or above
        for (std::size_t b = offset; b + 128 <= cur.size(); b += 128) {
          const std::size_t at = b + rng.below(128);
          switch (rng.below(6)) {
            case 0: prev[at] = 0x7FFF; cur[at] = 0; break;
            case 1: cur[at] = 0x7FFF; prev[at] = 0; break;
            case 2: (rng.below(2) ? cur[at] : prev[at]) = static_cast<fw::Pixel>(0x8000 + rng.below(0x8000)); break;
            default: break;
          }
        }
        INFO("path " << fw::detail::to_string(path) << " width " << width << " offset " << offset);
        CHECK(compare(path, cur, prev, sets, offset) == 0);
      }
    }
  }
}

TEST_CASE("nuc_line equals its definition on random and edge data", "[kernels][nuc]") {
  SplitMix64 rng(17);
  for (std::size_t width : {1, 7, 15, 16, 17, 31, 32, 33, 63, 64, 65, 160, 640, 1317}) {
    std::vector<fw::Pixel> in(width), out(width);
    std::vector<std::uint16_t> gain(width);
    std::vector<std::int16_t> offset(width);
    for (int round = 0; round < 20; ++round) {
      for (std::size_t i = 0; i < width; ++i) {
        const bool edge = rng.below(3) == 0;
        in[i] = edge ? kEdgePixels[rng.below(static_cast<std::uint32_t>(kEdgePixels.size()))]
                     : static_cast<fw::Pixel>(rng.next());
        gain[i] = rng.below(4) == 0 ? static_cast<std::uint16_t>(rng.next())
                                    : static_cast<std::uint16_t>(0xFFFF - rng.below(3));
        if (round % 2 == 0) gain[i] = static_cast<std::uint16_t>(rng.next());
        offset[i] = static_cast<std::int16_t>(rng.next());
      }
      fw::nuc_line(in.data(), gain.data(), offset.data(), out.data(), width);
      std::size_t differing = 0;
      for (std::size_t i = 0; i < width; ++i) {
        const std::int64_t scaled = (std::int64_t{in[i]} * gain[i] + 8192) >> 14;
        const std::int64_t want = std::clamp<std::int64_t>(scaled + offset[i], 0, 65535);
        differing += out[i] != want ? 1u : 0u;
      }
      CHECK(differing == 0);
    }
  }
}

// The NUC paths against the portable loop: random and edge lines, lines in the NEON kernel's
// 16-bit case (pixels below 2^14, gains below 2^15) with one pixel or gain outside it, every
// width of a step and its tail, unaligned starts.
TEST_CASE("every nuc_line path equals the portable loop", "[kernels][nuc]") {
  const auto portable = fw::detail::nuc_line_kernel(KernelPath::portable);
  REQUIRE(portable != nullptr);
  std::vector<KernelPath> paths;
  for (KernelPath p : fw::detail::kKernelPaths)
    if (p != KernelPath::portable && fw::detail::nuc_line_kernel(p) != nullptr) paths.push_back(p);
  if (paths.empty()) std::printf("nuc_line: only the portable path on this build\n");
  SplitMix64 rng(19);
  const std::vector<fw::Pixel> outside_in = {0x4000, 0x7FFF, 0x8000, 0xFFFF};
  const std::vector<std::uint16_t> outside_gain = {0x8000, 0xFFFF};
  for (std::size_t width : {1, 7, 8, 9, 15, 16, 17, 31, 32, 33, 64, 160, 640, 1317}) {
    for (std::size_t start : {0, 3}) {
      const std::size_t n = start + width;
      std::vector<fw::Pixel> in(n), want(n), got(n);
      std::vector<std::uint16_t> gain(n);
      std::vector<std::int16_t> offset(n);
      for (int round = 0; round < 24; ++round) {
        const bool narrow = round % 3 != 0;
        for (std::size_t i = 0; i < n; ++i) {
          if (narrow) {
            in[i] = static_cast<fw::Pixel>(rng.below(8) == 0 ? (rng.below(2) ? 0 : 0x3FFF)
                                                             : rng.below(0x4000));
            gain[i] = static_cast<std::uint16_t>(rng.below(4) == 0 ? rng.below(0x8000)
                                                                   : 16384 - 512 + rng.below(1024));
          } else {
            in[i] = rng.below(3) == 0
                        ? kEdgePixels[rng.below(static_cast<std::uint32_t>(kEdgePixels.size()))]
                        : static_cast<fw::Pixel>(rng.next());
            gain[i] = static_cast<std::uint16_t>(rng.next());
          }
          offset[i] = static_cast<std::int16_t>(rng.below(3) == 0 ? rng.next() & 0xFFFF
                                                                  : rng.below(201) - 100);
        }
        if (narrow && round % 3 == 1)
          in[start + rng.below(static_cast<std::uint32_t>(width))] =
              outside_in[rng.below(static_cast<std::uint32_t>(outside_in.size()))];
        if (narrow && round % 6 == 2)
          gain[start + rng.below(static_cast<std::uint32_t>(width))] =
              outside_gain[rng.below(static_cast<std::uint32_t>(outside_gain.size()))];
        portable(in.data() + start, gain.data() + start, offset.data() + start,
                 want.data() + start, width);
        for (KernelPath path : paths) {
          INFO("path " << fw::detail::to_string(path) << " width " << width << " round " << round);
          std::fill(got.begin(), got.end(), fw::Pixel{0xA5A5});
          fw::detail::nuc_line_kernel(path)(in.data() + start, gain.data() + start,
                                            offset.data() + start, got.data() + start, width);
          CHECK(std::equal(got.begin() + static_cast<std::ptrdiff_t>(start), got.end(),
                           want.begin() + static_cast<std::ptrdiff_t>(start)));
          CHECK(std::all_of(got.begin(), got.begin() + static_cast<std::ptrdiff_t>(start),
                            [](fw::Pixel p) { return p == 0xA5A5; }));
        }
      }
    }
  }
}

#if defined(__ARM_NEON)
// A build for a NEON target runs the NEON kernels (and so the comparisons above test them).
TEST_CASE("a NEON build selects the NEON kernels", "[kernels][neon]") {
  CHECK(fw::detail::selected_kernel_path() == KernelPath::neon);
  CHECK(fw::detail::correct_line_kernel(KernelPath::neon) != nullptr);
  CHECK(fw::detail::correct_update_kernel(KernelPath::neon) != nullptr);
  CHECK(fw::detail::nuc_line_kernel(KernelPath::neon) != nullptr);
  CHECK(fw::detail::ingest_kernel(KernelPath::neon) != nullptr);
  CHECK(fw::detail::ingest_rows_kernel(KernelPath::neon) != nullptr);
}
#endif
