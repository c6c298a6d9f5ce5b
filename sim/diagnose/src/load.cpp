// Reads a whole recording into float arrays; a diagnosis needs random access over time.

#include <algorithm>
#include <cmath>

#include "bolo/diagnose/baseline.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::diag {
namespace {

double median_of_known(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// Each frame's t_s, exposure and the readout after it, as the baseline's Eq. 6 needs them. What
// frames.csv leaves empty: t_s on the nominal period; an exposure, the median of the known ones
// (half the period if none is known); a readout, the interval to the next frame less the
// exposure when both time stamps are known, else the median of the known readouts, else the
// rest of the period.
void fill_frame_timing(const std::vector<rec::FrameRow>& rows, double period, const std::string& file, DiagnoseData& d) {
  std::vector<double> exposures, readouts;
  for (const auto& r : rows) {
    if (r.exposure_s) exposures.push_back(*r.exposure_s);
    if (r.readout_s) readouts.push_back(*r.readout_s);
  }
  const double typical_exposure = exposures.empty() ? 0.5 * period : median_of_known(exposures);
  const std::size_t N = rows.size();
  d.timing_filled = 0;
  for (std::size_t n = 0; n < N; ++n) {
    const auto& r = rows[n];
    if (r.exposure_s && !(*r.exposure_s > 0))
      throw rec::Error(file + ": frame " + std::to_string(n) + ": field exposure_s: 0 (a frame needs a positive exposure)");
    d.t_s.push_back(r.t_s.value_or(n > 0 && rows[n - 1].t_s ? *rows[n - 1].t_s + period : double(n) * period));
    d.exposure_s.push_back(r.exposure_s.value_or(typical_exposure));
    double readout = 0;
    if (r.readout_s) {
      readout = *r.readout_s;
    } else if (n + 1 < N && r.t_s && rows[n + 1].t_s && *rows[n + 1].t_s - *r.t_s > d.exposure_s.back()) {
      readout = *rows[n + 1].t_s - *r.t_s - d.exposure_s.back();
    } else if (!readouts.empty()) {
      readout = median_of_known(readouts);
    } else {
      readout = std::max(0.0, period - d.exposure_s.back());
    }
    d.readout_s.push_back(readout);
    d.timing_filled += !r.exposure_s || !r.readout_s;
  }
}

}  // namespace

DiagnoseData load_for_diagnosis(const std::filesystem::path& path) {
  rec::Recording rec(path);
  DiagnoseData d;
  d.name = path.filename().string();
  if (d.name.empty()) d.name = path.parent_path().filename().string();
  d.units = rec::to_string(rec.info().units);
  d.shape = {static_cast<int>(rec.frame_count()), static_cast<int>(rec.height()), static_cast<int>(rec.width())};
  if (d.shape.n < 2)
    throw rec::Error(path.string() + "/frames.npy: " + std::to_string(d.shape.n) +
                     " frame(s): diagnosis needs at least 2");
  const std::size_t P = d.shape.pixels();
  d.recorded.resize(d.shape.size());
  std::vector<std::uint16_t> raw(P);
  for (int n = 0; n < d.shape.n; ++n) {
    rec.read_frame(n, raw);
    float* f = d.frame(d.recorded, n);
    for (std::size_t p = 0; p < P; ++p) f[p] = raw[p];
  }
  // Readings at the format's floor or ceiling (recording.json `bits`) are clipped, not measured.
  const float ceiling = static_cast<float>(std::ldexp(1.0, static_cast<int>(rec.info().bits)) - 1.0);
  d.unclipped.assign(d.shape.size(), 1);
  for (std::size_t i = 0; i < d.shape.size(); ++i)
    if (d.recorded[i] <= 0.0f || d.recorded[i] >= ceiling) d.unclipped[i] = 0;
  // A pixel at the floor or ceiling in every frame is stuck (dead_pixels' evidence), not clipped.
  for (std::size_t p = 0; p < P; ++p) {
    int clipped = 0;
    for (int n = 0; n < d.shape.n; ++n) clipped += !d.unclipped[std::size_t(n) * P + p];
    if (clipped == d.shape.n)
      for (int n = 0; n < d.shape.n; ++n) d.unclipped[std::size_t(n) * P + p] = 1;
    else
      d.clipped_count += std::size_t(clipped);
  }
  d.reset_valid();
  d.has_scene = rec.has_scene();
  if (d.has_scene) {
    d.input.resize(d.shape.size());
    for (int n = 0; n < d.shape.n; ++n) {
      std::span<float> s(d.frame(d.input, n), P);
      rec.read_scene(n, s);
      for (std::size_t p = 0; p < P; ++p)
        if (!std::isfinite(s[p]))
          throw rec::Error(path.string() + "/scene.npy: frame " + std::to_string(n) + ": pixel " +
                           std::to_string(p) + ": not a finite number");
    }
  }
  const auto& rows = rec.rows();
  const double fps_info = rec.info().fps.value_or(0.0);
  // Frame period: from the time stamps when they are all there, else from recording.json.
  bool all_times = true;
  for (const auto& r : rows) all_times = all_times && r.t_s.has_value();
  double period = fps_info > 0 ? 1.0 / fps_info : 0.0;
  if (all_times && rows.size() > 1)
    period = (*rows.back().t_s - *rows.front().t_s) / double(rows.size() - 1);
  if (!(period > 0))
    throw rec::Error(path.string() + "/frames.csv: field t_s: no time stamps and recording.json has no fps");
  d.fps = 1.0 / period;
  fill_frame_timing(rows, period, path.string() + "/frames.csv", d);
  for (const auto& r : rows) {
    d.flagged_event.push_back(r.ffc.value_or(false) ? 1 : 0);
    d.fpa_temp_c.push_back(r.fpa_temp_c);
  }
  return d;
}

}  // namespace bolo::diag
