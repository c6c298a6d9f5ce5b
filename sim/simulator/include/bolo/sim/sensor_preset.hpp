#pragma once
// Sensor presets: the size, bit depth, frame rate, time constant and response of common uncooled
// cores, from their public datasheets (rounded; a starting point, not a calibration).

#include <string>
#include <vector>

namespace bolo::sim {

struct SensorPreset {
  std::string name;
  std::string sensor;          // recording.json "sensor"
  unsigned width = 160, height = 120;
  unsigned bits = 14;
  double fps = 30.0;
  double tau_s = 0.012;        // thermal time constant (tau_h = tau_c)
  double level_300k = 8000.0;  // raw counts of a 300 K scene
  double counts_per_kelvin = 40.0;
  double noise_counts = 2.0;   // temporal noise, standard deviation
};

const std::vector<SensorPreset>& sensor_presets();
// Throws std::invalid_argument naming the preset and listing the known ones.
const SensorPreset& sensor_preset(const std::string& name);

}  // namespace bolo::sim
