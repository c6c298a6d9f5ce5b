// Every catalogue effect is present in the output at the requested magnitude, with the signature
// ../shared/docs/diagnosis.md gives it, and absent without it. Each check compares a simulation
// with the effect against the same simulation (same seed, same scene) without it.

#include <catch2/catch.hpp>

#include <cmath>
#include <numeric>
#include <vector>

#include "bolo/sim/simulator.hpp"

using namespace bolo;
using sim::SimulatedFrame;

namespace {

constexpr std::uint32_t W = 48, H = 36;

sim::SimulatorConfig config(double noise = 0.0) {
  sim::SimulatorConfig c;
  c.info.width = W;
  c.info.height = H;
  c.info.bits = 16;
  c.info.fps = 60;
  c.info.exposure_s = 0.5 / 60;
  c.info.readout_s = 0.5 / 60;
  c.info.tau_h_s = c.info.tau_c_s = 0.012;
  c.info.reference_level = 8000;
  c.info.seed = 5;
  c.noise_counts = noise;
  return c;
}

sim::InputSampler uniform(float level) {
  return [level](double, std::span<float> out) { std::fill(out.begin(), out.end(), level); };
}

// A bright vertical bar `width` px wide moving right at `speed` px/s over an 8000-count background.
sim::InputSampler moving_bar(double speed = 600.0, double width = 6) {
  return [speed, width](double t, std::span<float> out) {
    const double x0 = 4 + speed * t;
    for (std::uint32_t r = 0; r < H; ++r)
      for (std::uint32_t c = 0; c < W; ++c)
        out[std::size_t{r} * W + c] = (c >= x0 && c < x0 + width) ? 12000.0f : 8000.0f;
  };
}

std::vector<SimulatedFrame> run(sim::SimulatorConfig c, const sim::InputSampler& input, int frames,
                                const std::vector<std::string>& effects = {}) {
  for (const auto& e : effects) c.effects.push_back(sim::parse_effect(e));
  sim::Simulator s(c, input);
  std::vector<SimulatedFrame> out(static_cast<std::size_t>(frames));
  for (auto& f : out) s.next(f);
  return out;
}

// Per pixel: with - without, for one frame.
std::vector<double> residual(const SimulatedFrame& with, const SimulatedFrame& without) {
  std::vector<double> r(with.counts.size());
  for (std::size_t p = 0; p < r.size(); ++p) r[p] = static_cast<double>(with.counts[p]) - without.counts[p];
  return r;
}

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size()); }
double stddev(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

}  // namespace

TEST_CASE("without effects and noise the simulator is the baseline exactly", "[sim][effects]") {
  const auto a = run(config(), uniform(8000), 5);
  for (const auto& f : a)
    for (auto v : f.counts) REQUIRE(v == 8000);  // te = tr and tau_h = tau_c: steady state = input
}

TEST_CASE("offset_fpn, column_fpn, row_fpn: static patterns of the requested sigma", "[sim][effects]") {
  const auto base = run(config(), uniform(8000), 3);
  const auto off = run(config(), uniform(8000), 3, {"offset_fpn:sigma=6"});
  const auto r0 = residual(off[0], base[0]), r2 = residual(off[2], base[2]);
  CHECK(stddev(r0) == Approx(6).epsilon(0.1));
  CHECK(r0 == r2);  // static

  const auto col = run(config(), uniform(8000), 2, {"column_fpn:sigma=4"});
  const auto rc = residual(col[1], base[1]);
  std::vector<double> column_means(W);
  for (std::uint32_t c = 0; c < W; ++c) {
    for (std::uint32_t r = 0; r < H; ++r) {
      CHECK(std::abs(rc[r * W + c] - rc[c]) <= 1.0);  // one value per column (up to rounding)
      column_means[c] += rc[r * W + c] / H;
    }
  }
  CHECK(stddev(column_means) == Approx(4).epsilon(0.3));

  const auto row = run(config(), uniform(8000), 2, {"row_fpn:sigma=4"});
  const auto rr = residual(row[1], base[1]);
  std::vector<double> row_means(H);
  for (std::uint32_t r = 0; r < H; ++r)
    for (std::uint32_t c = 0; c < W; ++c) row_means[r] += rr[r * W + c] / W;
  CHECK(stddev(row_means) == Approx(4).epsilon(0.35));
  CHECK(std::abs(rr[5 * W + 0] - rr[5 * W + 40]) <= 1.0);
}

TEST_CASE("gain_fpn: residual proportional to level", "[sim][effects]") {
  const auto lo = run(config(), uniform(4000), 2, {"gain_fpn:sigma=0.02"});
  const auto hi = run(config(), uniform(12000), 2, {"gain_fpn:sigma=0.02"});
  std::vector<double> g_lo, g_hi;
  for (std::size_t p = 0; p < lo[1].counts.size(); ++p) {
    g_lo.push_back(lo[1].counts[p] / 4000.0 - 1);
    g_hi.push_back(hi[1].counts[p] / 12000.0 - 1);
  }
  CHECK(stddev(g_hi) == Approx(0.02).epsilon(0.1));
  for (std::size_t p = 0; p < g_lo.size(); p += 97) CHECK(g_hi[p] == Approx(g_lo[p]).margin(3e-4));
}

TEST_CASE("shading: amplitude at the corners, nothing at the centre", "[sim][effects]") {
  const auto base = run(config(), uniform(8000), 2);
  const auto s = run(config(), uniform(8000), 2, {"shading:amplitude=40"});
  const auto r = residual(s[1], base[1]);
  CHECK(r[0] == Approx(40).margin(1));
  CHECK(r[W * H - 1] == Approx(40).margin(1));
  CHECK(std::abs(r[(H / 2) * W + W / 2]) <= 1.0);
}

TEST_CASE("fpa_drift and ffc_step: drift since the last shutter event, steps at events", "[sim][effects]") {
  const auto base = run(config(), uniform(8000), 30);
  const auto drift = run(config(), uniform(8000), 30, {"fpa_drift:rate=2,k=10"});
  for (int i : {0, 10, 29}) {
    const double t = i / 60.0;
    CHECK(mean(residual(drift[i], base[i])) == Approx(10 * 2 * t).margin(0.6));
    CHECK(*drift[i].row.fpa_temp_c == Approx(30 + 2 * t));
  }
  CHECK(!base[3].row.fpa_temp_c.has_value());

  const auto both = run(config(), uniform(8000), 30, {"ffc_step:every=10,step=20", "fpa_drift:rate=2,k=10"});
  for (int i = 0; i < 30; ++i) CHECK(*both[i].row.ffc == (i == 10 || i == 20));
  // Drift restarts at each event (sawtooth); the offset jumps by 10..20 counts there.
  const double before = mean(residual(both[9], base[9])), after = mean(residual(both[10], base[10]));
  const double drift_lost = 10 * 2 * (9 / 60.0);
  CHECK(std::abs(after - (before - drift_lost)) >= 9.5);
  CHECK(std::abs(after - (before - drift_lost)) <= 20.5);
  const auto hidden = run(config(), uniform(8000), 12, {"ffc_step:frames=5,flagged=0"});
  for (const auto& f : hidden) CHECK(*f.row.ffc == false);
}

TEST_CASE("dead_pixels and frame_duplication", "[sim][effects]") {
  const auto d = run(config(2), uniform(8000), 3, {"dead_pixels:count=7"});
  int stuck = 0;
  for (auto v : d[2].counts) stuck += (v == 0 || v == 65535);
  CHECK(stuck == 7);
  const auto dup = run(config(2), moving_bar(), 10, {"frame_duplication:every=5"});
  CHECK(dup[4].counts == dup[3].counts);
  CHECK(dup[9].counts == dup[8].counts);
  CHECK(dup[5].counts != dup[4].counts);
}

TEST_CASE("temporal_filter: lag-1 correlated noise in a static scene", "[sim][effects]") {
  auto lag1 = [](const std::vector<SimulatedFrame>& frames) {
    double num = 0, den = 0;
    for (std::size_t p = 0; p < frames[0].counts.size(); p += 3)
      for (std::size_t i = 11; i < frames.size(); ++i) {
        const double a = frames[i].counts[p] - 8000.0, b = frames[i - 1].counts[p] - 8000.0;
        num += a * b;
        den += a * a;
      }
    return num / den;
  };
  CHECK(std::abs(lag1(run(config(20), uniform(8000), 40))) < 0.05);
  CHECK(lag1(run(config(20), uniform(8000), 40, {"temporal_filter:alpha=0.6"})) == Approx(0.6).margin(0.06));
}

TEST_CASE("agc: static pixels change when something changes elsewhere", "[sim][effects]") {
  auto appearing = [](double t, std::span<float> out) {
    for (std::uint32_t r = 0; r < H; ++r)
      for (std::uint32_t c = 0; c < W; ++c)
        out[std::size_t{r} * W + c] = 8000.0f + 10.0f * static_cast<float>(c) + ((t > 0.1 && c > W / 2) ? 5000.0f : 0.0f);
  };
  const auto plain = run(config(), appearing, 15);
  const auto agc = run(config(), appearing, 15, {"agc:damping=1"});
  CHECK(plain[14].counts[5] == plain[2].counts[5]);           // a static pixel on the left
  CHECK(std::abs(int{agc[14].counts[5]} - int{agc[2].counts[5]}) > 500);
}

TEST_CASE("crosstalk and nonlinearity", "[sim][effects]") {
  auto hot_pixel = [](double, std::span<float> out) {
    std::fill(out.begin(), out.end(), 8000.0f);
    out[10 * W + 10] = 10000.0f;
  };
  const auto x = run(config(), hot_pixel, 2, {"crosstalk:epsilon=0.2"});
  CHECK(x[1].counts[10 * W + 10] == Approx(10000 - 0.2 * 2000).margin(1));  // under-reads
  CHECK(x[1].counts[10 * W + 11] == Approx(8000 + 0.2 * 2000 / 4).margin(1));
  const auto n = run(config(), uniform(10000), 2, {"nonlinearity:c=1e-5"});
  CHECK(n[1].counts[0] == Approx(10000 - 1e-5 * 2000 * 2000).margin(1));
}

TEST_CASE("rolling_readout: a moving edge is sheared in proportion to the row", "[sim][effects]") {
  auto edge_column = [](const SimulatedFrame& f, std::uint32_t row) {
    for (std::uint32_t c = 0; c < W; ++c)
      if (f.counts[row * W + c] > 9000) return static_cast<int>(c);
    return -1;
  };
  sim::SimulatorConfig c = config();
  c.substeps = 8;
  const double line = 1.0 / 60 / H;  // rows read one after another over a whole period
  const auto plain = run(c, moving_bar(300, 12), 4);
  const auto rolled = run(c, moving_bar(300, 12), 4, {"rolling_readout:line_time_s=" + std::to_string(line)});
  REQUIRE(edge_column(plain[2], 0) > 0);
  CHECK(edge_column(plain[2], 0) == edge_column(plain[2], H - 1));
  const double expected_shift = 300 * line * (H - 1);  // ~4.9 px
  CHECK(edge_column(rolled[2], H - 1) - edge_column(rolled[2], 0) == Approx(expected_shift).margin(1.0));
  CHECK(edge_column(rolled[2], 0) == edge_column(plain[2], 0));
}

TEST_CASE("thermal_memory: a slow second path, tau2 and weight as requested", "[sim][effects]") {
  const auto base = run(config(), uniform(8000), 40);
  const auto m = run(config(), uniform(8000), 40, {"thermal_memory:tau2_s=0.2,weight=0.05"});
  for (int i : {0, 10, 39}) {
    const double expected = 0.05 * 8000 * (1 - std::pow(std::exp(-1 / 60.0 / 0.2), i + 1));
    CHECK(mean(residual(m[i], base[i])) == Approx(expected).margin(0.6));
  }
}

TEST_CASE("tau_spread: no residual in a static scene, residual where the scene moves", "[sim][effects]") {
  const auto s_static = run(config(), uniform(8000), 5, {"tau_spread:sigma=0.2"});
  for (auto v : s_static[4].counts) REQUIRE(v == 8000);
  const auto base = run(config(), moving_bar(), 8);
  const auto spread = run(config(), moving_bar(), 8, {"tau_spread:sigma=0.2"});
  const auto r = residual(spread[6], base[6]);
  double moving = 0;
  for (double v : r) moving = std::max(moving, std::abs(v));
  CHECK(moving > 50);
}

TEST_CASE("tau_temperature: rising and falling steps differ", "[sim][effects]") {
  auto step = [](float from, float to) {
    return [from, to](double t, std::span<float> out) {
      std::fill(out.begin(), out.end(), t < 0.1 ? from : to);
    };
  };
  // With gamma = 0, the response to a step up mirrors the step down.
  auto asym = [&](const std::vector<std::string>& effects) {
    const auto up = run(config(), step(6000, 10000), 10, effects);
    const auto down = run(config(), step(10000, 6000), 10, effects);
    const int k = 6;  // the first frame after the step
    return (up[k].counts[0] - 6000.0) / 4000.0 - (10000.0 - down[k].counts[0]) / 4000.0;
  };
  CHECK(std::abs(asym({})) < 1e-3);
  CHECK(std::abs(asym({"tau_temperature:gamma=1e-4"})) > 0.02);
}

TEST_CASE("bad effects are refused with the effect and parameter named", "[sim][effects]") {
  auto error = [](const std::string& text) {
    try {
      run(config(), uniform(8000), 1, {text});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(error("warp_drive") .find("unknown effect") != std::string::npos);
  CHECK(error("offset_fpn:sigma=-1").find("offset_fpn: sigma") != std::string::npos);
  CHECK(error("offset_fpn:sgima=1").find("sgima: unknown parameter") != std::string::npos);
  CHECK(error("thermal_memory:tau2_s=abc").find("not a number") != std::string::npos);
  CHECK(error("ffc_step").find("every=N or frames") != std::string::npos);
  CHECK(error("offset_fpn:sigma").find("expected key=value") != std::string::npos);
  CHECK(sim::effect_ids().size() == 17);
}

TEST_CASE("deterministic from the seed: same seed same bits, another seed other noise and maps", "[sim][effects]") {
  const std::vector<std::string> effects = {"offset_fpn:sigma=3", "dead_pixels:count=5", "tau_spread:sigma=0.1"};
  auto c1 = config(3.0), c2 = config(3.0);
  c2.info.seed = 6;
  c1.noise_1f_counts = c2.noise_1f_counts = 1.0;
  const auto a = run(c1, moving_bar(), 6, effects), b = run(c1, moving_bar(), 6, effects);
  const auto other = run(c2, moving_bar(), 6, effects);
  for (int i = 0; i < 6; ++i) {
    CHECK(a[i].counts == b[i].counts);
    CHECK(a[i].counts != other[i].counts);
    CHECK(a[i].scene == other[i].scene);  // the scene itself does not depend on the seed
  }
}
