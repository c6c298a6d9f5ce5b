#include "path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bolo::sim::scene::detail {
namespace {

constexpr double kRamp = 0.3;  // fraction of a turn over which curvature ramps in (and out)

double ramp_integral(double x) { return x * x * x - 0.5 * x * x * x * x; }  // int_0^x 3u^2-2u^3
double ramp(double x) { return x * x * (3.0 - 2.0 * x); }

// Normalised heading progress W(sigma)/W(1) of a turn, sigma in [0, 1].
double turn_progress(double sigma) {
  const double r = kRamp;
  double w;
  if (sigma <= 0.0) {
    w = 0.0;
  } else if (sigma < r) {
    w = r * ramp_integral(sigma / r);
  } else if (sigma <= 1.0 - r) {
    w = 0.5 * r + (sigma - r);
  } else if (sigma < 1.0) {
    w = 0.5 * r + (1.0 - 2.0 * r) + r * (0.5 - ramp_integral((1.0 - sigma) / r));
  } else {
    w = 1.0 - r;
  }
  return w / (1.0 - r);
}

double turn_profile(double sigma) {  // curvature shape, normalised so its integral is 1
  const double r = kRamp;
  double w;
  if (sigma <= 0.0 || sigma >= 1.0) w = 0.0;
  else if (sigma < r) w = ramp(sigma / r);
  else if (sigma <= 1.0 - r) w = 1.0;
  else w = ramp((1.0 - sigma) / r);
  return w / (1.0 - r);
}

}  // namespace

PlanarPath::PlanarPath(const Eigen::Vector2d& start, double heading, std::vector<Segment> segments)
    : start_(start), heading0_(heading), segments_(std::move(segments)) {
  double s = 0.0, h = heading;
  for (const auto& g : segments_) {
    if (!(g.length > 0.0)) throw std::invalid_argument("path: segment length must be positive");
    seg_start_.push_back(s);
    seg_heading_.push_back(h);
    s += g.length;
    h += g.turn;
  }
  length_ = s;
  const std::size_t n = static_cast<std::size_t>(std::ceil(length_ / ds_));
  ds_ = length_ / static_cast<double>(std::max<std::size_t>(n, 1));
  table_.resize(std::max<std::size_t>(n, 1) + 1);
  table_[0] = start_;
  constexpr int kSub = 4;  // Simpson sub-intervals per table step
  for (std::size_t k = 0; k + 1 < table_.size(); ++k) {
    const double s0 = static_cast<double>(k) * ds_;
    const double hstep = ds_ / kSub;
    Eigen::Vector2d acc = Eigen::Vector2d::Zero();
    for (int i = 0; i <= kSub; ++i) {
      const double hh = heading_at(s0 + i * hstep);
      const double wgt = (i == 0 || i == kSub) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      acc += wgt * Eigen::Vector2d(std::cos(hh), std::sin(hh));
    }
    table_[k + 1] = table_[k] + acc * (hstep / 3.0);
  }
}

double PlanarPath::heading_at(double s) const {
  if (segments_.empty()) return heading0_;
  if (s <= 0.0) return heading0_;
  if (s >= length_) return seg_heading_.back() + segments_.back().turn;
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(seg_start_.begin(), seg_start_.end(), s) - seg_start_.begin()) - 1;
  const Segment& g = segments_[i];
  if (g.turn == 0.0) return seg_heading_[i];
  return seg_heading_[i] + g.turn * turn_progress((s - seg_start_[i]) / g.length);
}

double PlanarPath::curvature_at(double s) const {
  if (segments_.empty() || s <= 0.0 || s >= length_) return 0.0;
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(seg_start_.begin(), seg_start_.end(), s) - seg_start_.begin()) - 1;
  const Segment& g = segments_[i];
  return g.turn / g.length * turn_profile((s - seg_start_[i]) / g.length);
}

PlanarPath::State PlanarPath::at(double s) const {
  if (s <= 0.0) {
    return {start_ + s * Eigen::Vector2d(std::cos(heading0_), std::sin(heading0_)), heading0_};
  }
  if (s >= length_) {
    const double h = heading_at(length_);
    return {table_.back() + (s - length_) * Eigen::Vector2d(std::cos(h), std::sin(h)), h};
  }
  std::size_t k = static_cast<std::size_t>(s / ds_);
  if (k + 1 >= table_.size()) k = table_.size() - 2;
  const double s0 = static_cast<double>(k) * ds_;
  const double tau = (s - s0) / ds_;
  const double h0 = heading_at(s0), h1 = heading_at(s0 + ds_);
  const Eigen::Vector2d m0(std::cos(h0), std::sin(h0)), m1(std::cos(h1), std::sin(h1));
  const double t2 = tau * tau, t3 = t2 * tau;
  const Eigen::Vector2d p = (2 * t3 - 3 * t2 + 1) * table_[k] + (t3 - 2 * t2 + tau) * ds_ * m0 +
                            (-2 * t3 + 3 * t2) * table_[k + 1] + (t3 - t2) * ds_ * m1;
  return {p, heading_at(s)};
}

Eigen::Vector2d turn_displacement(double length, double turn) {
  PlanarPath p(Eigen::Vector2d::Zero(), 0.0, {{length, turn}});
  return p.at(length).p;
}

}  // namespace bolo::sim::scene::detail
