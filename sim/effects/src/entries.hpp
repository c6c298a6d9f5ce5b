#pragma once
// Each effect's catalogue entry (id, schema, both halves), defined in its family's file and
// listed once in catalogue.cpp.

#include <memory>
#include <utility>

#include "bolo/effects/catalogue.hpp"

namespace bolo::effects {

EffectEntry thermal_memory();     // thermal.cpp
EffectEntry tau_temperature();    // thermal.cpp
EffectEntry rolling_readout();    // readout.cpp
EffectEntry crosstalk();          // readout.cpp
EffectEntry nonlinearity();       // readout.cpp
EffectEntry offset_fpn();         // static_maps.cpp
EffectEntry column_fpn();         // static_maps.cpp
EffectEntry row_fpn();            // static_maps.cpp
EffectEntry shading();            // static_maps.cpp
EffectEntry gain_fpn();           // slope_maps.cpp
EffectEntry tau_spread();         // slope_maps.cpp
EffectEntry ffc_step();           // events.cpp
EffectEntry fpa_drift();          // events.cpp
EffectEntry temporal_filter();    // core_processing.cpp
EffectEntry dead_pixels();        // core_processing.cpp
EffectEntry frame_duplication();  // core_processing.cpp
EffectEntry agc();                // agc.cpp

// An entry whose halves are built from the spec and the simulation (Apply) and from nothing (Fit).
template <typename Apply, typename Fit>
EffectEntry make_entry(std::string_view id, std::vector<Param> params) {
  return {id, std::move(params),
          [](const sim::EffectSpec& s, const sim::SimulationInfo& i) -> std::unique_ptr<sim::Effect> {
            return std::make_unique<Apply>(s, i);
          },
          []() -> std::unique_ptr<diag::Candidate> { return std::make_unique<Fit>(); }};
}

}  // namespace bolo::effects
