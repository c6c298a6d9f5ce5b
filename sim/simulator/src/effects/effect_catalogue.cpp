// The catalogue: ids in the order the effects act along the chain (which is why it is a list,
// not a map): shutter events before the drift they reset; pixel physics (thermal memory,
// crosstalk, response) before the gain and offsets the readout adds; the core's processing last.

#include <stdexcept>

#include "effects.hpp"

namespace bolo::sim {
namespace {

using Factory = std::unique_ptr<Effect> (*)(const EffectSpec&, const SimulationInfo&);
struct Entry {
  const char* id;
  Factory make;
};

const std::vector<Entry>& catalogue() {
  using namespace effects;
  static const std::vector<Entry> entries = {
      {"rolling_readout", make_rolling_readout}, {"tau_spread", make_tau_spread},
      {"tau_temperature", make_tau_temperature}, {"thermal_memory", make_thermal_memory},
      {"crosstalk", make_crosstalk},             {"nonlinearity", make_nonlinearity},
      {"gain_fpn", make_gain_fpn},               {"offset_fpn", make_offset_fpn},
      {"column_fpn", make_column_fpn},           {"row_fpn", make_row_fpn},
      {"shading", make_shading},                 {"ffc_step", make_ffc_step},
      {"fpa_drift", make_fpa_drift},             {"temporal_filter", make_temporal_filter},
      {"agc", make_agc},                         {"dead_pixels", make_dead_pixels},
      {"frame_duplication", make_frame_duplication},
  };
  return entries;
}

}  // namespace

const std::vector<std::string>& effect_ids() {
  static const std::vector<std::string> ids = [] {
    std::vector<std::string> out;
    for (const Entry& e : catalogue()) out.emplace_back(e.id);
    return out;
  }();
  return ids;
}

std::unique_ptr<Effect> make_effect(const EffectSpec& spec, const SimulationInfo& info) {
  const auto& entries = catalogue();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (spec.id != entries[i].id) continue;
    std::unique_ptr<Effect> effect = entries[i].make(spec, info);
    effect->order = static_cast<int>(i);
    return effect;
  }
  std::string known;
  for (const Entry& e : entries) known += (known.empty() ? "" : ", ") + std::string(e.id);
  throw std::invalid_argument("--effect " + spec.id + ": unknown effect (known: " + known + ")");
}

}  // namespace bolo::sim
