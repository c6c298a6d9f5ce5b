// The catalogue: entries in the order the effects act along the chain (which is why it is a
// list, not a map): shutter events before the drift they reset; pixel physics (thermal memory,
// crosstalk, response) before the gain and offsets the readout adds; the core's processing last.

#include "bolo/effects/catalogue.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "entries.hpp"

namespace bolo::effects {

const std::vector<EffectEntry>& catalogue() {
  static const std::vector<EffectEntry> entries = [] {
    struct Row {
      EffectEntry (*entry)();
      int diagnosis_rank;
    };
    const Row rows[] = {
        {rolling_readout, 12}, {tau_spread, 9},   {tau_temperature, 11}, {thermal_memory, 10},
        {crosstalk, 13},       {nonlinearity, 14}, {gain_fpn, 8},         {offset_fpn, 4},
        {column_fpn, 5},       {row_fpn, 6},       {shading, 7},          {ffc_step, 0},
        {fpa_drift, 1},        {temporal_filter, 15}, {agc, 16},          {dead_pixels, 3},
        {frame_duplication, 2},
    };
    std::vector<EffectEntry> out;
    for (const Row& row : rows) {
      out.push_back(row.entry());
      out.back().diagnosis_rank = row.diagnosis_rank;
    }
    return out;
  }();
  return entries;
}

const EffectEntry* find(std::string_view id) {
  for (const EffectEntry& e : catalogue())
    if (e.id == id) return &e;
  return nullptr;
}

std::vector<std::unique_ptr<diag::Candidate>> make_candidates() {
  std::vector<const EffectEntry*> ranked;
  for (const EffectEntry& e : catalogue()) ranked.push_back(&e);
  std::sort(ranked.begin(), ranked.end(),
            [](const EffectEntry* a, const EffectEntry* b) { return a->diagnosis_rank < b->diagnosis_rank; });
  std::vector<std::unique_ptr<diag::Candidate>> out;
  for (const EffectEntry* e : ranked) out.push_back(e->fit());
  return out;
}

}  // namespace bolo::effects

namespace bolo::sim {

const std::vector<std::string>& effect_ids() {
  static const std::vector<std::string> ids = [] {
    std::vector<std::string> out;
    for (const effects::EffectEntry& e : effects::catalogue()) out.emplace_back(e.id);
    return out;
  }();
  return ids;
}

std::unique_ptr<Effect> make_effect(const EffectSpec& spec, const SimulationInfo& info) {
  const auto& entries = effects::catalogue();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (spec.id != entries[i].id) continue;
    std::unique_ptr<Effect> effect = entries[i].apply(spec, info);
    effect->order = static_cast<int>(i);
    return effect;
  }
  std::string known;
  for (const effects::EffectEntry& e : entries) known += (known.empty() ? "" : ", ") + std::string(e.id);
  throw std::invalid_argument("--effect " + spec.id + ": unknown effect (known: " + known + ")");
}

}  // namespace bolo::sim
