// The two-frame corrector: coefficients, the per-pixel kernel, and the stage's rules for when a
// frame may be corrected against its predecessor.

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "bolo/firmware/two_frame_corrector.hpp"
#include "frame_collector.hpp"

using namespace bolo;
using bolo::test::HashingCollector;
using bolo::test::push_frame;
using bolo::test::SplitMix64;

namespace {

constexpr long double kQ24 = 16777216.0L;

// What the kernel must return, computed exactly: round half away from zero, clamp to u16.
fw::Pixel exact_output(fw::Pixel cur, fw::Pixel prev, fw::CorrectorCoefficients c) {
  const std::int64_t d = std::int64_t{cur} * c.gain_q24 - std::int64_t{prev} * c.carry_q24;
  const long double v = std::round(static_cast<long double>(d) / kQ24);  // std::round: ties away
  return static_cast<fw::Pixel>(std::clamp(v, 0.0L, 65535.0L));
}

fw::FrameHeader header(std::uint32_t w, std::uint32_t h, std::uint64_t seq, double t_s,
                       std::uint32_t exposure_ns = 10'000'000, std::uint32_t readout_ns = 6'000'000) {
  fw::FrameHeader hd;
  hd.width = w;
  hd.height = h;
  hd.sequence = seq;
  hd.sequence_valid = true;
  hd.timestamp_ns = static_cast<std::int64_t>(std::llround(t_s * 1e9));
  hd.timestamp_valid = true;
  hd.exposure_ns = exposure_ns;
  hd.readout_ns = readout_ns;
  hd.ffc = fw::FfcState::none;
  return hd;
}

struct Rig {
  static constexpr std::uint32_t W = 8, H = 4;
  explicit Rig(fw::CorrectorConfig cfg = config())
      : storage(fw::TwoFrameCorrector::storage_pixels(W, H)),
        sink(W, H),
        corrector(cfg, storage, sink) {}
  static fw::CorrectorConfig config() {
    fw::CorrectorConfig c;
    c.width = W;
    c.height = H;
    c.tau = {12'000'000, 12'000'000};
    return c;
  }
  fw::CarryOver run(const fw::FrameHeader& hd, fw::Pixel value) {
    push_frame(corrector, hd, std::vector<fw::Pixel>(std::size_t{hd.width} * hd.height, value));
    return corrector.last_frame().carry_over;
  }
  std::vector<fw::Pixel> storage;
  HashingCollector sink;
  fw::TwoFrameCorrector corrector;
};

}  // namespace

// What matters is the error a coefficient puts into an output pixel: |dG| * I + |dA| * I_prev with
// I up to 65535 / g (above that the output saturates) and I_prev up to 65535.
TEST_CASE("coefficient errors move no output pixel by more than 0.05 LSB", "[corrector][coefficients]") {
  long double worst_gain = 0, worst_carry = 0;
  for (double tau_h_ms : {1.0, 5.0, 8.0, 12.0, 15.0, 40.0}) {
    for (double tau_c_ms : {1.0, 8.0, 12.0, 15.0, 40.0}) {
      for (double te_ms : {0.5, 1.0, 4.0, 10.0, 16.6, 33.0, 100.0}) {
        for (double tr_ms : {0.0, 0.1, 2.0, 6.0, 16.6, 100.0, 1000.0}) {
          const fw::TimeConstants tau{static_cast<std::uint32_t>(tau_h_ms * 1e6),
                                      static_cast<std::uint32_t>(tau_c_ms * 1e6)};
          fw::CorrectorCoefficients c;
          const auto status = fw::compute_coefficients(
              tau, static_cast<std::uint32_t>(te_ms * 1e6), static_cast<std::uint32_t>(tr_ms * 1e6), c);
          const long double g = 1.0L / (1.0L - std::exp(-static_cast<long double>(te_ms) / tau_h_ms));
          const long double a = std::exp(-static_cast<long double>(tr_ms) / tau_c_ms);
          if (g >= 255.9L) {
            CHECK(status == fw::CoefficientStatus::gain_out_of_range);
            continue;
          }
          REQUIRE(status == fw::CoefficientStatus::ok);
          const long double gain_err = std::abs(c.gain_q24 / kQ24 - g) * 65535.0L / g;
          const long double carry_err = std::abs(c.carry_q24 / kQ24 - a * g) * 65535.0L;
          worst_gain = std::max(worst_gain, gain_err);
          worst_carry = std::max(worst_carry, carry_err);
        }
      }
    }
  }
  INFO("worst output error from coefficients (LSB): gain " << static_cast<double>(worst_gain)
                                                            << ", carry " << static_cast<double>(worst_carry));
  CHECK(worst_gain < 0.05L);
  CHECK(worst_carry < 0.05L);
}

TEST_CASE("coefficient refusals", "[corrector][coefficients]") {
  fw::CorrectorCoefficients c;
  CHECK(fw::compute_coefficients({0, 12'000'000}, 10'000'000, 1'000'000, c) ==
        fw::CoefficientStatus::zero_time_constant);
  CHECK(fw::compute_coefficients({12'000'000, 0}, 10'000'000, 1'000'000, c) ==
        fw::CoefficientStatus::zero_time_constant);
  CHECK(fw::compute_coefficients({12'000'000, 12'000'000}, 0, 1'000'000, c) ==
        fw::CoefficientStatus::zero_exposure);
  // t_e / tau_h = 1e-4: g would be ~10000
  CHECK(fw::compute_coefficients({12'000'000, 12'000'000}, 1'200, 1'000'000, c) ==
        fw::CoefficientStatus::gain_out_of_range);
  // no readout time: nothing cools, a = 1, so A == G
  REQUIRE(fw::compute_coefficients({12'000'000, 12'000'000}, 10'000'000, 0, c) ==
          fw::CoefficientStatus::ok);
  CHECK(c.carry_q24 == c.gain_q24);
}

TEST_CASE("the kernel is exactly round-half-away of G*cur - A*prev, clamped", "[corrector][kernel]") {
  SplitMix64 rng(42);
  const std::vector<fw::Pixel> edges = {0, 1, 2, 127, 128, 255, 256, 8191, 16383, 16384,
                                        32767, 32768, 65534, 65535};
  std::vector<fw::CorrectorCoefficients> coefficient_sets = {
      {1u << 24, 0}, {1u << 24, 1u << 24}, {0xFFFFFFFFu, 0}, {0xFFFFFFFFu, 0xFFFFFFFFu},
      {1u << 24, 1}, {29'000'000, 7}, {1, 0}, {(1u << 24) + (1u << 23), 1u << 23}};
  for (int i = 0; i < 200; ++i) {
    const auto g = static_cast<std::uint32_t>(rng.next());
    coefficient_sets.push_back({g, static_cast<std::uint32_t>(rng.next() % (std::uint64_t{g} + 1))});
  }
  std::vector<fw::Pixel> cur, prev;
  for (fw::Pixel a : edges)
    for (fw::Pixel b : edges) {
      cur.push_back(a);
      prev.push_back(b);
    }
  for (int i = 0; i < 4000; ++i) {
    cur.push_back(static_cast<fw::Pixel>(rng.next()));
    prev.push_back(static_cast<fw::Pixel>(rng.next()));
  }
  std::vector<fw::Pixel> out(cur.size());
  std::size_t mismatches = 0;
  for (const auto& c : coefficient_sets) {
    std::uint32_t low = 0, high = 0;
    fw::correct_line(cur.data(), prev.data(), c, out.data(), cur.size(), low, high);
    std::uint32_t want_low = 0, want_high = 0;
    for (std::size_t i = 0; i < cur.size(); ++i) {
      const std::int64_t d = std::int64_t{cur[i]} * c.gain_q24 - std::int64_t{prev[i]} * c.carry_q24;
      const long double r = std::round(static_cast<long double>(d) / kQ24);
      want_low += d < -(std::int64_t{1} << 23) ? 1u : 0u;  // below -0.5: clamping changed it
      want_high += r > 65535 ? 1u : 0u;
      if (out[i] != exact_output(cur[i], prev[i], c)) ++mismatches;
    }
    CHECK(low == want_low);
    CHECK(high == want_high);
  }
  CHECK(mismatches == 0);
}

TEST_CASE("ties round away from zero", "[corrector][kernel]") {
  // G = 1.5: 1 * 1.5 = 1.5 -> 2, 3 * 1.5 = 4.5 -> 5
  const fw::CorrectorCoefficients c{(1u << 24) + (1u << 23), 0};
  const fw::Pixel cur[2] = {1, 3}, prev[2] = {0, 0};
  fw::Pixel out[2];
  std::uint32_t low = 0, high = 0;
  fw::correct_line(cur, prev, c, out, 2, low, high);
  CHECK(out[0] == 2);
  CHECK(out[1] == 5);
}

TEST_CASE("a frame is corrected against its predecessor only when the chain holds", "[corrector][stage]") {
  SECTION("first frame gets gain only, second the carry-over") {
    Rig rig;
    CHECK(rig.run(header(8, 4, 0, 0.0), 1000) == fw::CarryOver::first_frame);
    const fw::CorrectorCoefficients first = rig.corrector.last_frame().coefficients;
    CHECK(first.carry_q24 == 0);
    CHECK(rig.sink.frame()[0] == exact_output(1000, 0, first));
    CHECK(rig.run(header(8, 4, 1, 0.1), 1000) == fw::CarryOver::applied);
    const fw::CorrectorCoefficients c = rig.corrector.last_frame().coefficients;
    CHECK(c.carry_q24 > 0);
    CHECK(rig.sink.frame()[5] == exact_output(1000, 1000, c));
  }
  SECTION("sequence gap") {
    Rig rig;
    rig.run(header(8, 4, 0, 0.0), 1000);
    CHECK(rig.run(header(8, 4, 2, 0.1), 1000) == fw::CarryOver::sequence_gap);
  }
  SECTION("shutter event") {
    Rig rig;
    rig.run(header(8, 4, 0, 0.0), 1000);
    auto hd = header(8, 4, 1, 0.1);
    hd.ffc = fw::FfcState::completed;
    CHECK(rig.run(hd, 1000) == fw::CarryOver::ffc_event);
    CHECK(rig.run(header(8, 4, 2, 0.2), 1000) == fw::CarryOver::applied);
  }
  SECTION("timestamp gap against the learned period, and time going backwards") {
    Rig rig;
    for (int i = 0; i < 5; ++i) rig.run(header(8, 4, static_cast<std::uint64_t>(i), 0.1 * i), 1000);
    CHECK(rig.corrector.last_frame().carry_over == fw::CarryOver::applied);
    CHECK(rig.run(header(8, 4, 5, 0.4 + 0.16), 1000) == fw::CarryOver::timestamp_gap);
    CHECK(rig.run(header(8, 4, 6, 0.66), 1000) == fw::CarryOver::applied);
    CHECK(rig.run(header(8, 4, 7, 0.66), 1000) == fw::CarryOver::timestamp_not_increasing);
  }
  SECTION("timestamps far apart (a clock jump) are a gap, without overflow") {
    Rig rig;
    auto early = header(8, 4, 0, 0.0);
    early.timestamp_ns = INT64_MIN + 5;
    rig.run(early, 1000);
    auto mid = header(8, 4, 1, 0.0);
    mid.timestamp_ns = INT64_MIN + 100'000'005;
    CHECK(rig.run(mid, 1000) == fw::CarryOver::applied);
    auto late = header(8, 4, 2, 0.0);
    late.timestamp_ns = INT64_MAX;  // the difference does not fit int64
    CHECK(rig.run(late, 1000) == fw::CarryOver::timestamp_gap);
    auto back = header(8, 4, 3, 0.0);
    back.timestamp_ns = INT64_MIN;
    CHECK(rig.run(back, 1000) == fw::CarryOver::timestamp_not_increasing);
  }
  SECTION("a nominal period from the configuration") {
    auto cfg = Rig::config();
    cfg.nominal_frame_period_ns = 50'000'000;
    Rig rig(cfg);
    rig.run(header(8, 4, 0, 0.0), 1000);
    CHECK(rig.run(header(8, 4, 1, 0.1), 1000) == fw::CarryOver::timestamp_gap);
  }
  SECTION("format change passes the frame through and breaks the chain") {
    Rig rig;
    rig.run(header(8, 4, 0, 0.0), 1000);
    CHECK(rig.run(header(4, 4, 1, 0.1), 1000) == fw::CarryOver::format_change);
    CHECK(rig.sink.frame()[0] == 1000);
    CHECK(rig.run(header(8, 4, 2, 0.2), 1000) == fw::CarryOver::first_frame);
  }
  SECTION("an incomplete predecessor is not used") {
    Rig rig;
    const auto hd = header(8, 4, 0, 0.0);
    std::vector<fw::Pixel> line(8, 1000);
    rig.corrector.begin_frame(hd);
    rig.corrector.push_line(0, line);
    rig.corrector.end_frame();  // three lines never came
    CHECK(rig.run(header(8, 4, 1, 0.1), 1000) == fw::CarryOver::previous_incomplete);
  }
  SECTION("rows out of order or of the wrong width break the frame: passed on, no predecessor") {
    Rig rig;
    rig.run(header(8, 4, 0, 0.0), 1000);
    std::vector<fw::Pixel> line(8, 1000), short_line(5, 1000);
    rig.corrector.begin_frame(header(8, 4, 1, 0.1));
    rig.corrector.push_line(0, line);
    rig.corrector.push_line(0, line);  // repeated: row 1 never comes
    rig.corrector.push_line(2, line);
    rig.corrector.push_line(3, line);
    rig.corrector.end_frame();
    CHECK(rig.corrector.last_frame().rows_uncorrected == 3);
    CHECK(rig.sink.frame()[3 * 8] == 1000);  // passed on unchanged
    CHECK(rig.run(header(8, 4, 2, 0.2), 1000) == fw::CarryOver::previous_incomplete);
    rig.corrector.begin_frame(header(8, 4, 3, 0.3));
    rig.corrector.push_line(0, line);
    rig.corrector.push_line(1, short_line);
    rig.corrector.push_line(2, line);
    rig.corrector.push_line(3, line);
    rig.corrector.end_frame();
    CHECK(rig.run(header(8, 4, 4, 0.4), 1000) == fw::CarryOver::previous_incomplete);
    CHECK(rig.corrector.totals().by_reason[static_cast<int>(fw::CarryOver::first_frame)] == 1);
    // Rows past the height, in order, are passed on and never written to the frame store.
    rig.corrector.begin_frame(header(8, 4, 5, 0.5));
    for (std::uint32_t r = 0; r < 6; ++r) rig.corrector.push_line(r, line);
    rig.corrector.end_frame();
    CHECK(rig.corrector.last_frame().rows_uncorrected == 2);
    CHECK(rig.run(header(8, 4, 6, 0.6), 1000) == fw::CarryOver::previous_incomplete);
  }
  SECTION("missing timing: no exposure passes through, no readout gives gain only") {
    Rig rig;
    CHECK(rig.run(header(8, 4, 0, 0.0, 0, 0), 1234) == fw::CarryOver::missing_timing);
    CHECK(rig.sink.frame()[0] == 1234);
    CHECK(rig.run(header(8, 4, 1, 0.1, 10'000'000, 0), 1234) == fw::CarryOver::missing_timing);
    CHECK(rig.corrector.last_frame().coefficients.carry_q24 == 0);
    CHECK(rig.sink.frame()[0] > 1234);
  }
  SECTION("timing from the configuration where the header has none") {
    auto cfg = Rig::config();
    cfg.default_exposure_ns = 10'000'000;
    cfg.default_readout_ns = 6'000'000;
    Rig rig(cfg);
    rig.run(header(8, 4, 0, 0.0, 0, 0), 1000);
    CHECK(rig.run(header(8, 4, 1, 0.1, 0, 0), 1000) == fw::CarryOver::applied);
  }
  SECTION("unusable coefficients pass the frame through") {
    Rig rig;
    CHECK(rig.run(header(8, 4, 0, 0.0, 1'000, 0), 777) == fw::CarryOver::coefficient_error);
    CHECK(rig.corrector.last_frame().coefficient_status == fw::CoefficientStatus::gain_out_of_range);
    CHECK(rig.sink.frame()[3] == 777);
  }
  SECTION("totals count every reason") {
    Rig rig;
    rig.run(header(8, 4, 0, 0.0), 1000);
    rig.run(header(8, 4, 1, 0.1), 1000);
    rig.run(header(8, 4, 3, 0.3), 1000);
    const auto& t = rig.corrector.totals();
    CHECK(t.frames == 3);
    CHECK(t.by_reason[static_cast<int>(fw::CarryOver::first_frame)] == 1);
    CHECK(t.by_reason[static_cast<int>(fw::CarryOver::applied)] == 1);
    CHECK(t.by_reason[static_cast<int>(fw::CarryOver::sequence_gap)] == 1);
  }
}

TEST_CASE("saturation is counted and clamped at both rails", "[corrector][stage]") {
  Rig rig;
  rig.run(header(8, 4, 0, 0.0), 65535);
  CHECK(rig.corrector.last_frame().saturated_high == 32);
  CHECK(rig.sink.frame()[0] == 65535);
  // bright predecessor, dark frame with almost no cooling time: strongly negative
  rig.run(header(8, 4, 1, 0.1, 10'000'000, 100), 0);
  rig.run(header(8, 4, 2, 0.2), 0);
  rig.run(header(8, 4, 3, 0.3, 10'000'000, 100), 65535);
  rig.run(header(8, 4, 4, 0.4), 0);
  CHECK(rig.corrector.last_frame().saturated_low == 32);
  CHECK(rig.sink.frame()[7] == 0);
}

// The stage computes coefficients once per distinct (mode, exposure, readout) and reuses them
// while those stay: every frame's coefficients must still be those of its own header chain.
TEST_CASE("each frame's coefficients follow its exposure and its predecessor's readout",
          "[corrector][coefficients]") {
  Rig rig;
  const fw::TimeConstants tau = Rig::config().tau;
  const std::uint32_t exposures[] = {10'000'000, 10'000'000, 8'000'000, 10'000'000, 10'000'000,
                                     10'000'000, 10'000'000, 12'000'000, 12'000'000, 10'000'000};
  const std::uint32_t readouts[] = {6'000'000, 6'000'000, 6'000'000, 5'000'000, 5'000'000,
                                    6'000'000, 6'000'000, 6'000'000, 7'000'000, 7'000'000};
  std::uint32_t previous_readout = 0;
  for (std::size_t i = 0; i < std::size(exposures); ++i) {
    INFO("frame " << i);
    // Frame 6 breaks the chain (a sequence gap): gain only, then carry-over again.
    const std::uint64_t seq = i < 6 ? i : i + 1;
    rig.run(header(8, 4, seq, 0.1 * static_cast<double>(i), exposures[i], readouts[i]), 1000);
    fw::CorrectorCoefficients want;
    if (i == 0 || i == 6) {
      REQUIRE(fw::compute_gain_only(tau, exposures[i], want) == fw::CoefficientStatus::ok);
    } else {
      REQUIRE(fw::compute_coefficients(tau, exposures[i], previous_readout, want) ==
              fw::CoefficientStatus::ok);
    }
    const fw::CorrectorCoefficients got = rig.corrector.last_frame().coefficients;
    CHECK(got.gain_q24 == want.gain_q24);
    CHECK(got.carry_q24 == want.carry_q24);
    previous_readout = readouts[i];
  }
}
