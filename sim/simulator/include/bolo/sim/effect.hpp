#pragma once
// The simulator's half of the effect catalogue (bolo/effects/catalogue.hpp, sim/effects): each
// effect of ../shared/docs/diagnosis.md as a composable simulator module. Each effect hooks into
// the chain at its physical place:
//   scene -> [input effects] -> bolometer (tau per pixel) -> [reading effects] -> noise ->
//   [output effects] -> quantisation -> [final effects]
// and describes itself for truth/ (parameters, per-pixel maps). Effects draw their random maps
// from their own generator (seeded from the simulation seed and the effect id), so adding one
// effect never changes the noise or the maps of another.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace bolo::sim {

// "id:key=value,key=value"; list values separated by '/': "ffc_step:frames=100/250".
struct EffectSpec {
  std::string id;
  std::map<std::string, std::string> params;
};
EffectSpec parse_effect(const std::string& text);  // throws std::invalid_argument naming the text

// What every effect may know about the simulation.
struct SimulationInfo {
  std::uint32_t width = 0, height = 0;
  std::uint32_t bits = 14;
  double fps = 30.0;
  double exposure_s = 0.0, readout_s = 0.0;
  double tau_h_s = 0.012, tau_c_s = 0.012;
  double reference_level = 0.0;  // counts of a 300 K scene: the level effects are scaled around
  std::uint64_t seed = 1;
};

// Per-frame state shared along the chain.
struct FrameState {
  std::uint64_t index = 0;
  double t_s = 0.0;                    // start of the exposure
  double period_s = 0.0;
  bool shutter_event = false;          // a shutter/FFC event completed before this frame
  bool shutter_flagged = false;        // ... and the camera reports it (frames.csv ffc = 1)
  std::optional<double> fpa_temp_c;    // written to frames.csv when an effect models it
  std::span<const float> mean_input;   // the frame's input (counts), averaged over sub-steps
};

class Effect {
 public:
  virtual ~Effect() = default;
  virtual const char* id() const = 0;

  // Time offset of a row's exposure start (rolling readout); 0 for a global shutter.
  virtual double row_delay_s(std::uint32_t /*row*/) const { return 0.0; }
  // Decides shutter events and FPA temperature for the frame (before anything is simulated).
  virtual void begin_frame(FrameState& /*frame*/) {}
  // Per-pixel time constants for this frame; `previous` is the previous frame's reading.
  virtual void time_constants(const FrameState& /*frame*/, std::span<const double> /*previous*/,
                              std::span<double> /*tau_h*/, std::span<double> /*tau_c*/) {}
  // On the bolometer's reading, before noise (thermal and pixel physics, readout offsets).
  virtual void on_reading(const FrameState& /*frame*/, std::span<double> /*y*/) {}
  // After noise, before quantisation (processing inside the camera core).
  virtual void on_output(const FrameState& /*frame*/, std::span<double> /*y*/) {}
  // On the final counts (defective pixels, frame repetition).
  virtual void on_counts(const FrameState& /*frame*/, std::span<std::uint16_t> /*counts*/) {}

  // Parameters as used (with defaults filled in) for truth/effects.json.
  virtual nlohmann::json parameters() const = 0;
  // Per-pixel maps for truth/ as (name, H*W values), e.g. ("offset_fpn_offset", map).
  virtual std::vector<std::pair<std::string, std::vector<float>>> maps() const { return {}; }

  // Where an effect acts on the chain, in catalogue order (sim/effects/src/catalogue.cpp).
  int order = 0;
};

// All catalogue ids, in the order they act (both defined by the catalogue, sim/effects).
const std::vector<std::string>& effect_ids();
// Builds an effect; throws std::invalid_argument naming the effect and the bad or unknown parameter.
std::unique_ptr<Effect> make_effect(const EffectSpec& spec, const SimulationInfo& info);

}  // namespace bolo::sim
