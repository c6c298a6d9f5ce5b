#include "bolo/sim/sensor_preset.hpp"

#include <stdexcept>

namespace bolo::sim {

const std::vector<SensorPreset>& sensor_presets() {
  // Lepton: 26 Hz inside, 8.7 Hz exported; Boson: 60 Hz; Tau 2: 30 Hz. Time constants ~10-12 ms
  // (VOx microbolometers); responsivity ~25-50 counts/K at 14 bits (NETD ~40-50 mK).
  static const std::vector<SensorPreset> presets = {
      {"generic", "bolo simulate: generic 14-bit microbolometer", 160, 120, 14, 30.0, 0.012, 8000, 40, 2.0},
      {"lepton3", "FLIR Lepton 3 (simulated)", 160, 120, 14, 8.7, 0.012, 8000, 30, 2.5},
      {"boson640", "FLIR Boson 640 (simulated)", 640, 512, 14, 60.0, 0.0105, 8000, 45, 2.0},
      {"boson320", "FLIR Boson 320 (simulated)", 320, 256, 14, 60.0, 0.0105, 8000, 45, 2.0},
      {"tau2", "FLIR Tau 2 640 (simulated)", 640, 512, 14, 30.0, 0.012, 8000, 40, 2.5},
  };
  return presets;
}

const SensorPreset& sensor_preset(const std::string& name) {
  std::string known;
  for (const SensorPreset& p : sensor_presets()) {
    if (p.name == name) return p;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  throw std::invalid_argument("--preset " + name + ": unknown sensor preset (known: " + known + ")");
}

}  // namespace bolo::sim
