#pragma once
// Factories of the catalogue's effects (one per id), used by effect_catalogue.cpp.

#include <memory>

#include "bolo/sim/effect.hpp"

namespace bolo::sim::effects {

#define BOLO_EFFECT_FACTORY(name) \
  std::unique_ptr<Effect> make_##name(const EffectSpec& spec, const SimulationInfo& info);
BOLO_EFFECT_FACTORY(thermal_memory)
BOLO_EFFECT_FACTORY(tau_temperature)
BOLO_EFFECT_FACTORY(tau_spread)
BOLO_EFFECT_FACTORY(offset_fpn)
BOLO_EFFECT_FACTORY(gain_fpn)
BOLO_EFFECT_FACTORY(column_fpn)
BOLO_EFFECT_FACTORY(row_fpn)
BOLO_EFFECT_FACTORY(fpa_drift)
BOLO_EFFECT_FACTORY(ffc_step)
BOLO_EFFECT_FACTORY(shading)
BOLO_EFFECT_FACTORY(rolling_readout)
BOLO_EFFECT_FACTORY(nonlinearity)
BOLO_EFFECT_FACTORY(crosstalk)
BOLO_EFFECT_FACTORY(temporal_filter)
BOLO_EFFECT_FACTORY(dead_pixels)
BOLO_EFFECT_FACTORY(agc)
BOLO_EFFECT_FACTORY(frame_duplication)
#undef BOLO_EFFECT_FACTORY

}  // namespace bolo::sim::effects
