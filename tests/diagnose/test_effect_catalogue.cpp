// The effect catalogue (bolo/effects/catalogue.hpp) against ../shared/docs/diagnosis.md: every id
// of its table (and row_fpn, which the table names beside column_fpn) is registered once, with a
// parameter schema, a simulator half that runs in the chain on the schema's own values, and a
// diagnose half that fits on a recording the simulator made with the effect.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "bolo/diagnose/candidate.hpp"
#include "bolo/effects/catalogue.hpp"
#include "bolo/sim/simulator.hpp"

using namespace bolo;

namespace {

// diagnosis.md's "Effect names" table, in its order, and row_fpn.
const std::vector<std::string> kDiagnosisIds = {
    "thermal_memory", "tau_temperature", "tau_spread", "offset_fpn",      "gain_fpn",      "column_fpn",
    "fpa_drift",      "ffc_step",        "shading",    "rolling_readout", "nonlinearity",  "crosstalk",
    "temporal_filter", "dead_pixels",    "agc",        "frame_duplication", "row_fpn"};

constexpr std::uint32_t W = 24, H = 18;
constexpr int kFrames = 24;

sim::SimulatorConfig config() {
  sim::SimulatorConfig c;
  c.info.width = W;
  c.info.height = H;
  c.info.bits = 16;
  c.info.fps = 30;
  c.info.exposure_s = c.info.readout_s = 0.5 / 30;
  c.info.tau_h_s = c.info.tau_c_s = 0.012;
  c.info.reference_level = 8000;
  c.info.seed = 3;
  c.noise_counts = 1.0;
  return c;
}

// A bright bar crossing an 8000-count background.
void moving_bar(double t, std::span<float> out) {
  const double x0 = 2 + 120 * t;
  for (std::uint32_t r = 0; r < H; ++r)
    for (std::uint32_t c = 0; c < W; ++c) out[std::size_t{r} * W + c] = (c >= x0 && c < x0 + 4) ? 12000.0f : 8000.0f;
}

// Every schema key at its default, or at its lower bound where it has none.
sim::EffectSpec spec_from_schema(const effects::EffectEntry& e) {
  sim::EffectSpec spec{std::string(e.id), {}};
  for (const effects::Param& p : e.params) spec.params[std::string(p.name)] = std::to_string(std::isnan(p.fallback) ? p.lo : p.fallback);
  return spec;
}

std::vector<std::vector<std::uint16_t>> simulate(const std::vector<sim::EffectSpec>& effects) {
  sim::SimulatorConfig c = config();
  c.effects = effects;
  sim::Simulator s(c, moving_bar);
  std::vector<std::vector<std::uint16_t>> frames;
  sim::SimulatedFrame f;
  for (int n = 0; n < kFrames; ++n) {
    s.next(f);
    frames.push_back(f.counts);
  }
  return frames;
}

// The recording made with the effect, the baseline the same simulation without it.
diag::DiagnoseData data_for(const std::vector<std::vector<std::uint16_t>>& with,
                            const std::vector<std::vector<std::uint16_t>>& without) {
  diag::DiagnoseData d;
  d.shape = {kFrames, int(H), int(W)};
  for (int n = 0; n < kFrames; ++n) {
    d.recorded.insert(d.recorded.end(), with[n].begin(), with[n].end());
    d.baseline.insert(d.baseline.end(), without[n].begin(), without[n].end());
    d.t_s.push_back(n / 30.0);
  }
  d.input = d.baseline;
  d.valid.assign(d.shape.size(), 1);
  d.unclipped = d.valid;
  d.exposure_s.assign(kFrames, 0.5 / 30);
  d.readout_s.assign(kFrames, 0.5 / 30);
  d.flagged_event.assign(kFrames, 0);
  d.fpa_temp_c.assign(kFrames, std::nullopt);
  d.has_scene = true;
  d.fps = 30;
  d.tau_c_s = 0.012;
  d.level_mid = 8000;
  d.name = "catalogue";
  return d;
}

}  // namespace

TEST_CASE("every effect of diagnosis.md is registered once, with a schema", "[diagnose][effects]") {
  const auto& entries = effects::catalogue();
  for (const std::string& id : kDiagnosisIds) {
    INFO(id);
    CHECK(std::count_if(entries.begin(), entries.end(), [&](const auto& e) { return e.id == id; }) == 1);
    const effects::EffectEntry* e = effects::find(id);
    REQUIRE(e != nullptr);
    CHECK(e->apply != nullptr);
    CHECK(e->fit != nullptr);
    CHECK_FALSE(e->params.empty());
    std::set<std::string_view> names;
    for (const effects::Param& p : e->params) {
      INFO(p.name);
      CHECK_FALSE(p.name.empty());
      CHECK(names.insert(p.name).second);
      CHECK(p.lo <= p.hi);
      if (!std::isnan(p.fallback)) CHECK((p.fallback >= p.lo && p.fallback <= p.hi));
    }
  }
  CHECK(entries.size() == kDiagnosisIds.size());
  CHECK(sim::effect_ids().size() == entries.size());
  const auto candidates = effects::make_candidates();
  REQUIRE(candidates.size() == entries.size());
  std::set<std::string> fitted;
  for (const auto& c : candidates) fitted.insert(c->id());
  CHECK(fitted == std::set<std::string>(kDiagnosisIds.begin(), kDiagnosisIds.end()));
}

TEST_CASE("every entry is applied by the simulator and fitted by diagnose", "[diagnose][effects]") {
  const auto without = simulate({});
  for (const std::string& id : kDiagnosisIds) {
    INFO(id);
    const effects::EffectEntry* e = effects::find(id);
    REQUIRE(e != nullptr);
    const sim::EffectSpec spec = spec_from_schema(*e);
    // The simulator's half takes the schema's keys, names itself by the entry's id and reports
    // every schema parameter in truth/.
    const auto applied = e->apply(spec, config().info);
    REQUIRE(applied != nullptr);
    CHECK(applied->id() == id);
    const nlohmann::json used = applied->parameters();
    for (const effects::Param& p : e->params) CHECK(used.contains(std::string(p.name)));
    const auto with = simulate({spec});

    // Diagnose's half fits on that recording; a simulator text it writes uses the schema's keys.
    auto candidate = e->fit();
    REQUIRE(candidate != nullptr);
    CHECK(candidate->id() == id);
    diag::DiagnoseData d = data_for(with, without);
    std::vector<float> residual(d.shape.size());
    for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = d.recorded[i] - d.baseline[i];
    candidate->prepare(d, residual);
    const auto model = candidate->fit(std::vector<char>(kFrames, 1));
    if (model && !model->simulator_effect().empty()) {
      const sim::EffectSpec text = sim::parse_effect(model->simulator_effect());
      CHECK(text.id == id);
      for (const auto& entry : text.params) {
        const auto& key = entry.first;  // a named copy: clang 14 cannot capture a structured binding
        CHECK(std::any_of(e->params.begin(), e->params.end(), [&](const auto& p) { return p.name == key; }));
      }
    }
    candidate->release();
  }
}
