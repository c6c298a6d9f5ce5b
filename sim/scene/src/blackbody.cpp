#include "bolo/sim/scene/blackbody.hpp"

#include <cmath>
#include <stdexcept>

namespace bolo::sim::scene {

double BlackbodySchedule::period_s() const {
  return static_cast<double>(plateaus_k.size()) * plateau_s;
}

namespace {
// Time within the schedule's period and plateau index.
void locate(const BlackbodySchedule& s, double t, std::size_t& index, double& within) {
  const double period = s.period_s();
  double tp = std::fmod(t, period);
  if (tp < 0.0) tp += period;
  std::size_t i = static_cast<std::size_t>(std::floor(tp / s.plateau_s));
  if (i >= s.plateaus_k.size()) i = s.plateaus_k.size() - 1;
  index = i;
  within = tp - static_cast<double>(i) * s.plateau_s;
}
}  // namespace

double BlackbodySchedule::plateau_temperature(double t) const {
  validate();
  std::size_t i;
  double w;
  locate(*this, t, i, w);
  return plateaus_k[i];
}

bool BlackbodySchedule::chopper_closed(double t) const {
  validate();
  std::size_t i;
  double w;
  locate(*this, t, i, w);
  if (w < chopper_start_s || chopper_hz <= 0.0) return false;
  const double phase = std::fmod((w - chopper_start_s) * chopper_hz, 1.0);
  return phase >= open_fraction;
}

double BlackbodySchedule::temperature(double t) const {
  return chopper_closed(t) ? blade_k : plateau_temperature(t);
}

void BlackbodySchedule::validate() const {
  if (plateaus_k.empty()) throw std::invalid_argument("blackbody schedule: no plateaus");
  if (!(plateau_s > 0.0)) throw std::invalid_argument("blackbody schedule: plateau_s must be positive");
  if (!(chopper_hz >= 0.0) || !(open_fraction >= 0.0 && open_fraction <= 1.0) || !(chopper_start_s >= 0.0))
    throw std::invalid_argument("blackbody schedule: bad chopper timing");
}

}  // namespace bolo::sim::scene
