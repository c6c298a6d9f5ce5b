#include "bolo/sim/scene/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

namespace bolo::sim::scene {

Camera::Camera(std::uint32_t w, std::uint32_t h, double hfov) : width(w), height(h) {
  if (w == 0 || h == 0) throw std::invalid_argument("camera: size must be non-zero");
  if (!(hfov > 0.0 && hfov < 180.0))
    throw std::invalid_argument("camera: horizontal field of view " + std::to_string(hfov) +
                                " deg is outside (0, 180)");
  fx = fy = 0.5 * static_cast<double>(w) / std::tan(0.5 * hfov * std::numbers::pi / 180.0);
  cx = 0.5 * (static_cast<double>(w) - 1.0);
  cy = 0.5 * (static_cast<double>(h) - 1.0);
}

double Camera::hfov_deg() const {
  return 2.0 * std::atan(0.5 * static_cast<double>(width) / fx) * 180.0 / std::numbers::pi;
}
double Camera::vfov_deg() const {
  return 2.0 * std::atan(0.5 * static_cast<double>(height) / fy) * 180.0 / std::numbers::pi;
}

bool Camera::distorted() const {
  for (const double k : {k1, k2, k3, k4, k5, k6, p1, p2})
    if (k != 0.0) return true;
  return false;
}

namespace {

// The rational radial factor at r2 = x^2 + y^2 and its derivative with respect to r2.
struct Radial {
  double factor, d_r2;
};
Radial radial_at(const Camera& c, double r2) {
  const double num = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  const double den = 1.0 + r2 * (c.k4 + r2 * (c.k5 + r2 * c.k6));
  const double d_num = c.k1 + r2 * (2.0 * c.k2 + 3.0 * r2 * c.k3);
  const double d_den = c.k4 + r2 * (2.0 * c.k5 + 3.0 * r2 * c.k6);
  return {num / den, (d_num * den - num * d_den) / (den * den)};
}

}  // namespace

Eigen::Vector2d Camera::distort(const Eigen::Vector2d& n) const {
  const double x = n.x(), y = n.y();
  const double r2 = x * x + y * y;
  const double rad = radial_at(*this, r2).factor;
  return {x * rad + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * rad + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

Eigen::Vector2d Camera::undistort(const Eigen::Vector2d& d) const {
  if (!distorted()) return d;
  Eigen::Vector2d x = d;
  for (int it = 0; it < 60; ++it) {
    const double u = x.x(), v = x.y();
    const Radial r = radial_at(*this, u * u + v * v);
    const double rad = r.factor;
    const double drad = 2.0 * r.d_r2;  // d rad / d(u) = drad * u
    Eigen::Matrix2d j;
    j(0, 0) = rad + u * drad * u + 2.0 * p1 * v + 6.0 * p2 * u;
    j(0, 1) = u * drad * v + 2.0 * p1 * u + 2.0 * p2 * v;
    j(1, 0) = v * drad * u + 2.0 * p1 * u + 2.0 * p2 * v;
    j(1, 1) = rad + v * drad * v + 6.0 * p1 * v + 2.0 * p2 * u;
    const Eigen::Vector2d step = j.inverse() * (distort(x) - d);
    x -= step;
    if (!(step.norm() > 1e-15 * (1.0 + x.norm()))) break;
  }
  return x;
}

std::optional<Eigen::Vector2d> Camera::project(const Eigen::Vector3d& p) const {
  if (!(p.z() > 0.0)) return std::nullopt;
  const Eigen::Vector2d d = distort({p.x() / p.z(), p.y() / p.z()});
  return Eigen::Vector2d(fx * d.x() + cx, fy * d.y() + cy);
}

Eigen::Vector3d Camera::unproject(const Eigen::Vector2d& px) const {
  const Eigen::Vector2d n = undistort({(px.x() - cx) / fx, (px.y() - cy) / fy});
  return Eigen::Vector3d(n.x(), n.y(), 1.0).normalized();
}

nlohmann::json Camera::to_json() const {
  nlohmann::json j{{"model", "pinhole"}, {"fx", fx}, {"fy", fy}, {"cx", cx}, {"cy", cy},
                   {"k1", k1},           {"k2", k2}, {"p1", p1}, {"p2", p2}};
  if (k3 != 0.0 || k4 != 0.0 || k5 != 0.0 || k6 != 0.0) j["k3"] = k3, j["k4"] = k4, j["k5"] = k5, j["k6"] = k6;
  return j;
}

Camera Camera::from_json(const nlohmann::json& j, std::uint32_t w, std::uint32_t h) {
  if (!j.is_object()) throw std::invalid_argument("not a JSON object");
  // Other tools write only the numbers; the format's one model is then meant.
  if (j.contains("model") && !(j["model"].is_string() && j["model"].get<std::string>() == "pinhole"))
    throw std::invalid_argument("field model is not \"pinhole\" (the recording format's only camera model)");
  const auto number = [&](const char* key, bool required) -> double {
    if (!j.contains(key)) {
      if (required) throw std::invalid_argument(std::string("field ") + key + " is missing");
      return 0.0;
    }
    if (!j[key].is_number()) throw std::invalid_argument(std::string("field ") + key + " is not a number");
    const double value = j[key].get<double>();
    if (!std::isfinite(value)) throw std::invalid_argument(std::string("field ") + key + " is not finite");
    return value;
  };
  Camera c;
  c.width = w;
  c.height = h;
  c.fx = number("fx", true);
  c.fy = number("fy", true);
  c.cx = number("cx", true);
  c.cy = number("cy", true);
  if (!(c.fx > 0) || !(c.fy > 0)) throw std::invalid_argument("fields fx, fy must be positive");
  c.k1 = number("k1", false);
  c.k2 = number("k2", false);
  c.p1 = number("p1", false);
  c.p2 = number("p2", false);
  c.k3 = number("k3", false);
  c.k4 = number("k4", false);
  c.k5 = number("k5", false);
  c.k6 = number("k6", false);
  c.validate();
  return c;
}

void Camera::validate() const {
  if (width == 0 || height == 0) throw std::invalid_argument("camera: size must be non-zero");
  if (!(fx > 0.0) || !(fy > 0.0) || !std::isfinite(fx) || !std::isfinite(fy))
    throw std::invalid_argument("camera: focal lengths fx, fy must be positive and finite");
  for (double v : {cx, cy, k1, k2, k3, k4, k5, k6, p1, p2})
    if (!std::isfinite(v)) throw std::invalid_argument("camera: cx, cy and the distortion coefficients must be finite");
}

const char* distortion_problem(const Camera& c) {
  if (!c.distorted()) return nullptr;
  // The farthest corner's distorted radius; r times the radial factor must keep growing until it
  // is reached (a fold inside the image maps two directions onto one pixel; past a pole of the
  // denominator the radius turns negative, a fold too).
  double corner = 0.0;
  for (const double u : {-0.5, c.width - 0.5})
    for (const double v : {-0.5, c.height - 0.5})
      corner = std::max(corner, std::hypot((u - c.cx) / c.fx, (v - c.cy) / c.fy));
  const auto radial = [&](double r) { return r * radial_at(c, r * r).factor; };
  constexpr double kStep = 1e-3, kMaxRadius = 20.0;  // ~174 degrees across
  double r = 0.0, previous = 0.0;
  while (previous < corner * 1.05) {
    r += kStep;
    const double now = radial(r);
    if (!(now > previous)) return "the radial distortion (k1..k6) folds back inside the image";
    if (r > kMaxRadius) return "the distortion (k1..k6) needs a field of view beyond 174 degrees";
    previous = now;
  }
  // Tangential terms: the inverse must converge and the Jacobian stay positive over the image.
  constexpr int kGrid = 17;
  for (int gy = 0; gy < kGrid; ++gy)
    for (int gx = 0; gx < kGrid; ++gx) {
      const Eigen::Vector2d px(-0.5 + c.width * gx / (kGrid - 1.0), -0.5 + c.height * gy / (kGrid - 1.0));
      const Eigen::Vector2d d((px.x() - c.cx) / c.fx, (px.y() - c.cy) / c.fy);
      const Eigen::Vector2d n = c.undistort(d);
      if (!n.allFinite() || (c.distort(n) - d).norm() > 1e-9 * (1.0 + d.norm()))
        return "the distortion cannot be inverted over the image";
      const double h = 1e-6;
      const Eigen::Vector2d ex = (c.distort(n + Eigen::Vector2d(h, 0)) - c.distort(n - Eigen::Vector2d(h, 0))) / (2 * h);
      const Eigen::Vector2d ey = (c.distort(n + Eigen::Vector2d(0, h)) - c.distort(n - Eigen::Vector2d(0, h))) / (2 * h);
      if (!(ex.x() * ey.y() - ex.y() * ey.x() > 0.0)) return "the distortion folds over inside the image";
    }
  return nullptr;
}

}  // namespace bolo::sim::scene
