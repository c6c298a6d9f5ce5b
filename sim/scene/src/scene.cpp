#include "bolo/sim/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bolo::sim::scene {

double Sky::temperature(const Eigen::Vector3d& d) const {
  const double n = d.norm();
  const double s = n > 0.0 ? d.z() / n : 0.0;
  if (s <= 0.0) return horizon_k;
  return zenith_k + (horizon_k - zenith_k) * std::exp(-s / falloff);
}

std::size_t Scene::add_material(Material m) {
  materials.push_back(std::move(m));
  return materials.size() - 1;
}

int Scene::add_motion(Motion m) {
  motions.push_back(std::move(m));
  return static_cast<int>(motions.size()) - 1;
}

std::size_t Scene::add_quad(const Quad& q) {
  quads.push_back(q);
  return quads.size() - 1;
}

std::size_t Scene::add_box(const Box& b) {
  boxes.push_back(b);
  return boxes.size() - 1;
}

Eigen::Isometry3d Scene::box_to_world(const Box& b, double t) const {
  if (b.motion < 0) return b.placement;
  return motions.at(static_cast<std::size_t>(b.motion))(t) * b.placement;
}

void Scene::validate() const {
  const std::string where = "scene '" + name + "': ";
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const auto& m = materials[i];
    if (!std::isfinite(m.base_k) || !std::isfinite(m.noise_k) || !std::isfinite(m.detail_k) ||
        !(m.noise_scale_m > 0.0) || !(m.detail_scale_m > 0.0))
      throw std::invalid_argument(where + "material " + std::to_string(i) + " ('" + m.name +
                                  "') has a non-finite temperature or a non-positive noise scale");
  }
  for (std::size_t i = 0; i < quads.size(); ++i) {
    const auto& q = quads[i];
    const std::string what = where + "quad " + std::to_string(i);
    if (q.material >= materials.size())
      throw std::invalid_argument(what + ": material index " + std::to_string(q.material) + " out of range");
    if (std::abs(q.u_axis.norm() - 1.0) > 1e-9 || std::abs(q.v_axis.norm() - 1.0) > 1e-9 ||
        std::abs(q.u_axis.dot(q.v_axis)) > 1e-9)
      throw std::invalid_argument(what + ": u_axis and v_axis must be orthonormal");
    if (!q.origin.allFinite() || !(q.u_min <= q.u_max) || !(q.v_min <= q.v_max))
      throw std::invalid_argument(what + ": non-finite origin or empty extent");
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const auto& b = boxes[i];
    const std::string what = where + "box " + std::to_string(i);
    if (b.material >= materials.size())
      throw std::invalid_argument(what + ": material index " + std::to_string(b.material) + " out of range");
    if (b.motion >= static_cast<int>(motions.size()) || b.motion < -1)
      throw std::invalid_argument(what + ": motion index " + std::to_string(b.motion) + " out of range");
    if (b.motion >= 0 && !motions[static_cast<std::size_t>(b.motion)])
      throw std::invalid_argument(what + ": its motion is empty");
    if (!b.lo.allFinite() || !b.hi.allFinite() || (b.hi - b.lo).minCoeff() < 0.0)
      throw std::invalid_argument(what + ": lo must be <= hi and finite");
    const Eigen::Matrix3d r = b.placement.linear();
    if (!((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-9) || !b.placement.translation().allFinite())
      throw std::invalid_argument(what + ": placement must be a rigid transform");
  }
}

std::vector<std::string> scene_names() { return {"street", "lab", "checker"}; }

Scene make_scene(const std::string& name, std::uint64_t seed) {
  if (name == "street") return make_street_scene(seed);
  if (name == "lab") return make_lab_scene(BlackbodySchedule{}, seed);
  if (name == "checker") return make_checker_scene(seed);
  std::string valid;
  for (const auto& n : scene_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown scene '" + name + "' (valid scenes: " + valid + ")");
}

}  // namespace bolo::sim::scene
