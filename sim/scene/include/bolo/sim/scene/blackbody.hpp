#pragma once
// The blackbody experiment: a schedule of uniform temperature plateaus seen through a chopper.
// The `lab` scene's target radiates schedule.temperature(t); the `blackbody` trajectory looks at
// it from a fixed pose. The schedule repeats with period plateaus.size() * plateau_s.

#include <vector>

namespace bolo::sim::scene {

struct BlackbodySchedule {
  // Plateau temperatures (K), each held for plateau_s seconds; the change between plateaus is
  // an ideal step (a scene projector, not a slow oven).
  std::vector<double> plateaus_k = {293.15, 303.15, 313.15, 323.15, 333.15, 343.15, 318.15};
  double plateau_s = 10.0;
  // During [chopper_start_s, plateau_s) of every plateau an ideal chopper alternates between
  // the open target and its closed blade (at blade_k): a square wave of chopper_hz starting open,
  // closed during the second half (1 - open_fraction) of each period.
  double chopper_start_s = 6.0;
  double chopper_hz = 2.0;
  double open_fraction = 0.5;
  double blade_k = 296.15;

  double period_s() const;
  double plateau_temperature(double t) const;  // the source, chopper ignored
  bool chopper_closed(double t) const;
  double temperature(double t) const;          // what the camera sees: the source or the blade
  void validate() const;  // throws std::invalid_argument on an empty schedule or bad timing
};

}  // namespace bolo::sim::scene
