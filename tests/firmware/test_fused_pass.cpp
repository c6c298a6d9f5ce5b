// The Pipeline's fused NUC -> bad pixels -> corrector pass (FastPath::fused) must give exactly
// what the stages one after another give (FastPath::off): same output rows, pixels and order,
// same corrector and bad-pixel statistics, and the same frame store (seen through the next
// frames' outputs), for well-formed and broken frames pushed as lines and as runs.

#include <catch2/catch.hpp>

#include <cstddef>
#include <vector>

#include "bolo/firmware/detail/kernels.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "frame_collector.hpp"

using namespace bolo;
using bolo::test::SplitMix64;

namespace {

class EventHash final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& h) override { mix(0xB0 ^ h.sequence); }
  void push_line(std::uint32_t row, fw::LineView line) override {
    mix(0x11);
    mix(row);
    mix(line.size());
    for (fw::Pixel p : line) mix(p);
  }
  void end_frame() override { mix(0xE0); }
  std::uint64_t hash() const { return hash_; }

 private:
  void mix(std::uint64_t v) {
    hash_ ^= v;
    hash_ *= 0x100000001b3ull;
  }
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

fw::FrameHeader header(std::uint32_t w, std::uint32_t h, std::uint64_t seq) {
  fw::FrameHeader hd;
  hd.width = w;
  hd.height = h;
  hd.sequence = seq;
  hd.sequence_valid = true;
  hd.timestamp_ns = static_cast<std::int64_t>(seq) * 16'666'667;
  hd.timestamp_valid = true;
  hd.exposure_ns = 10'000'000;
  hd.readout_ns = 6'000'000;
  return hd;
}

}  // namespace

TEST_CASE("fused pipeline pass equals the stages one after another", "[pipeline][fused]") {
  SplitMix64 rng(99);
  for (std::uint32_t w : {1u, 31u, 32u, 160u, 161u, 640u, 1300u}) {
    const std::uint32_t h = w >= 640 ? 9 : 23;
    const std::size_t n = std::size_t{w} * h;
    std::vector<std::uint16_t> gain(n);
    std::vector<std::int16_t> offset(n);
    std::vector<std::uint8_t> mask(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t roll = rng.below(60);
      gain[i] = roll == 0 ? static_cast<std::uint16_t>(rng.next())  // some at or above 2.0
                          : static_cast<std::uint16_t>(16384 - 500 + rng.below(1000));
      offset[i] = roll == 1 ? static_cast<std::int16_t>(rng.next())
                            : static_cast<std::int16_t>(static_cast<int>(rng.below(400)) - 200);
      mask[i] = rng.below(30) == 0 ? 1 : 0;  // clusters too: some pixels unrepairable
      if (i % 97 == 5) mask[i] = 1;
    }
    for (int stuck_on = 0; stuck_on < 2; ++stuck_on) {
      fw::PipelineConfig cfg;
      cfg.corrector.width = w;
      cfg.corrector.height = h;
      cfg.corrector.tau = {11'000'000, 13'000'000};
      cfg.use_nuc = true;
      cfg.nuc.gain_q14 = gain;
      cfg.nuc.offset = offset;
      cfg.use_bad_pixels = true;
      cfg.bad_pixels.mask = mask;
      cfg.bad_pixels.detect_stuck = stuck_on != 0;
      fw::PipelineConfig off = cfg;
      off.fast_path = fw::FastPath::off;
      cfg.fast_path = fw::FastPath::fused;
      std::vector<fw::Pixel> arena_a(fw::Pipeline::arena_pixels(off)), arena_b(arena_a.size());
      EventHash out_a, out_b;
      fw::Pipeline a(off, arena_a, out_a), b(cfg, arena_b, out_b);
      REQUIRE_FALSE(a.fused_pass());
      REQUIRE(b.fused_pass());
      std::vector<fw::Pixel> frame(n + 8 * w);
      for (std::uint64_t seq = 1; seq <= 12; ++seq) {
        for (fw::Pixel& p : frame) {
          const std::uint32_t pick = rng.below(50);
          p = static_cast<fw::Pixel>(pick == 0   ? 0x3FFF
                                     : pick == 1 ? 0
                                     : pick < 5  ? rng.below(65536)
                                                 : 6000 + rng.below(4000));
        }
        const fw::FrameHeader hd = header(w, h, seq);
        a.input().begin_frame(hd);
        b.input().begin_frame(hd);
        const int kind = static_cast<int>(rng.below(6));  // 0..2 well-formed, 3 cut, 4 skip, 5 width
        std::uint32_t row = 0;
        const std::uint32_t cut = kind == 3 ? rng.below(h) : h;
        while (row < cut) {
          const std::uint32_t count = std::min(cut - row, 1 + rng.below(kind == 0 ? h : 5));
          const std::size_t stride = kind == 1 ? w + 3 : w;
          const fw::Pixel* at = frame.data() + std::size_t{row} * stride;
          if (kind == 2) {  // single lines
            for (std::uint32_t i = 0; i < count; ++i) {
              a.input().push_line(row + i, fw::LineView(at + i * stride, w));
              b.input().push_line(row + i, fw::LineView(at + i * stride, w));
            }
          } else {
            a.input().push_lines(row, count, at, w, stride);
            b.input().push_lines(row, count, at, w, stride);
          }
          row += count;
          if (kind == 4 && row < h && rng.below(3) == 0) ++row;  // a row skipped
          if (kind == 5 && rng.below(4) == 0 && w > 1) {           // a short line
            a.input().push_line(row, fw::LineView(at, w - 1));
            b.input().push_line(row, fw::LineView(at, w - 1));
          }
        }
        a.input().end_frame();
        b.input().end_frame();
        INFO("width " << w << " frame " << seq << " kind " << kind << " stuck " << stuck_on);
        REQUIRE(out_a.hash() == out_b.hash());
        const fw::CorrectorFrameStats& x = a.corrector().last_frame();
        const fw::CorrectorFrameStats& y = b.corrector().last_frame();
        REQUIRE(x.carry_over == y.carry_over);
        REQUIRE(x.saturated_low == y.saturated_low);
        REQUIRE(x.saturated_high == y.saturated_high);
        REQUIRE(x.rows_uncorrected == y.rows_uncorrected);
        REQUIRE(a.bad_pixels()->last_frame().replaced == b.bad_pixels()->last_frame().replaced);
        REQUIRE(a.bad_pixels()->last_frame().unrepairable ==
                b.bad_pixels()->last_frame().unrepairable);
      }
    }
  }
}

TEST_CASE("every fused-pass kernel equals the portable definition", "[kernels][fused]") {
  using fw::detail::KernelPath;
  SplitMix64 rng(5);
  for (KernelPath path : fw::detail::kKernelPaths) {
    const fw::detail::FusedRowsFn kernel = fw::detail::fused_rows_kernel(path);
    if (path == KernelPath::portable || kernel == nullptr) continue;
    for (std::size_t width : {1, 31, 32, 33, 128, 160, 161, 640}) {
      for (std::size_t rows : {1, 3, 12}) {
        const std::size_t n = width * rows;
        const std::size_t flag_bytes = fw::detail::flag_line_bytes(width);
        std::vector<fw::Pixel> in(n), store(n);
        std::vector<std::uint16_t> gain(n);
        std::vector<std::int16_t> off(n);
        std::vector<std::uint8_t> mask(flag_bytes * rows);
        for (int round = 0; round < 12; ++round) {
          for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t roll = rng.below(64);
            in[i] = static_cast<fw::Pixel>(roll == 0 ? rng.next() : roll == 1 ? 0x3FFF : 5000 + rng.below(6000));
            store[i] = static_cast<fw::Pixel>(roll == 2 ? rng.next() : 5000 + rng.below(6000));
            gain[i] = static_cast<std::uint16_t>(roll == 3 ? rng.next() : 16384 - 300 + rng.below(600));
            off[i] = static_cast<std::int16_t>(roll == 4 ? rng.next() : static_cast<int>(rng.below(100)) - 50);
          }
          for (std::size_t r = 0; r < rows; ++r) {
            std::vector<std::uint8_t> bytes(width);
            for (auto& b : bytes) b = rng.below(40) == 0 ? 1 : 0;
            fw::detail::pack_mask_bits(bytes.data(), width, mask.data() + r * flag_bytes);
          }
          fw::CorrectorCoefficients c;
          // wide coefficients (G >= 2^28), small ones (a wrapped NUC value can give a value in
          // range: the input test must catch it), usual ones
          c.gain_q24 = round % 3 == 2   ? (1u << 28) + rng.below(1u << 20)
                       : round % 3 == 1 ? rng.below(1u << 12)
                                        : (1u << 24) + rng.below(1u << 22);
          c.carry_q24 = round % 3 == 1 ? rng.below(1u << 8) : rng.below(1u << 23);
          const auto run = [&](fw::detail::FusedRowsFn f, std::vector<fw::Pixel>& st,
                               std::vector<fw::Pixel>& out, std::vector<std::uint8_t>& flags,
                               std::uint32_t& lo, std::uint32_t& hi) {
            fw::detail::IngestLine j{in.data(), gain.data(), off.data(),
                                     round % 2 ? mask.data() : nullptr, round % 4 < 3, 0, 0x3FFF,
                                     out.data(), flags.data(), width, round % 5 == 0};
            return f({j, st.data(), c}, rows, width, lo, hi);
          };
          std::vector<fw::Pixel> st_a = store, st_b = store, out_a(n), out_b(n);
          std::vector<std::uint8_t> fl_a(flag_bytes * rows), fl_b(fl_a.size());
          std::uint32_t lo_a = 0, hi_a = 0, lo_b = 0, hi_b = 0;
          const std::uint64_t any_a = run(fw::detail::fused_rows_kernel(KernelPath::portable), st_a,
                                          out_a, fl_a, lo_a, hi_a);
          const std::uint64_t any_b = run(kernel, st_b, out_b, fl_b, lo_b, hi_b);
          INFO("path " << fw::detail::to_string(path) << " width " << width << " rows " << rows
                       << " round " << round);
          CHECK(any_a == any_b);
          CHECK(st_a == st_b);
          CHECK(out_a == out_b);
          CHECK(fl_a == fl_b);
          CHECK(lo_a == lo_b);
          CHECK(hi_a == hi_b);
        }
      }
    }
  }
}
