#pragma once
// Pinhole camera with OpenCV's rational radial (k1..k6) and tangential (p1, p2) distortion: the
// `camera.json` model of the recording format (docs: ../shared/docs/recording-format.md).
//
// Camera frame: x right, y down, z forward. Pixel coordinates: (u, v) = (column, row) with the
// centre of the top-left pixel at (0, 0), so the image spans [-0.5, W-0.5] x [-0.5, H-0.5].
//
// Projection of a camera-frame point (X, Y, Z), Z > 0:
//   x = X/Z, y = Y/Z, r2 = x^2 + y^2
//   radial = (1 + k1 r2 + k2 r2^2 + k3 r2^3) / (1 + k4 r2 + k5 r2^2 + k6 r2^3)
//   xd = x radial + 2 p1 x y + p2 (r2 + 2 x^2)
//   yd = y radial + p1 (r2 + 2 y^2) + 2 p2 x y
//   u = fx xd + cx,  v = fy yd + cy
// (OpenCV's convention; with k3..k6 = 0 Brown-Conrady's). Unprojection inverts the distortion
// with Newton's method; it is exact to ~1e-12 px wherever the distortion is monotonic.

#include <cstdint>
#include <optional>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace bolo::sim::scene {

struct Camera {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  double fx = 0.0, fy = 0.0;  // focal lengths, pixels
  double cx = 0.0, cy = 0.0;  // principal point, pixels (top-left pixel centre = (0, 0))
  double k1 = 0.0, k2 = 0.0, k3 = 0.0;  // radial distortion, numerator
  double k4 = 0.0, k5 = 0.0, k6 = 0.0;  // radial distortion, denominator
  double p1 = 0.0, p2 = 0.0;            // tangential distortion

  Camera() = default;
  // Square pixels, principal point at the image centre ((W-1)/2, (H-1)/2), no distortion;
  // `hfov_deg` is the full horizontal field of view across the W pixels (edge to edge).
  // Throws std::invalid_argument for a zero size or a field of view outside (0, 180).
  Camera(std::uint32_t width, std::uint32_t height, double hfov_deg);

  double hfov_deg() const;  // of the undistorted pinhole, edge to edge
  double vfov_deg() const;
  bool distorted() const;  // any distortion coefficient non-zero

  // Normalised image coordinates (x/z, y/z) -> distorted normalised coordinates, and back.
  Eigen::Vector2d distort(const Eigen::Vector2d& undistorted) const;
  Eigen::Vector2d undistort(const Eigen::Vector2d& distorted) const;

  // Camera-frame point -> pixel; nullopt behind (or on) the camera plane z <= 0.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_camera) const;
  // Pixel -> unit-length ray direction in the camera frame (z > 0).
  Eigen::Vector3d unproject(const Eigen::Vector2d& pixel) const;

  // Exactly the camera.json object of the recording format:
  // {"model": "pinhole", "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"}, plus "k3".."k6" when
  // any of them is non-zero (no size: that is in recording.json).
  nlohmann::json to_json() const;
  // The inverse; missing distortion keys mean 0, a missing model means "pinhole", other keys
  // (e.g. OpenCV's "distortion_model" note) are ignored. Throws
  // std::invalid_argument naming the field ("field fx is missing", ...; the caller names the file)
  // when the model is not "pinhole", a required number is missing, or a number is not finite or
  // a focal length not positive.
  static Camera from_json(const nlohmann::json& j, std::uint32_t width, std::uint32_t height);

  void validate() const;  // throws std::invalid_argument on a zero size or non-positive focal
};

// Why the camera's distortion cannot be inverted over its image (nullptr when it can): the
// radial distortion folds back before the image's corners (r times the radial factor stops
// growing; a pole of its denominator included), or the inverse does not converge or the
// mapping's Jacobian is not positive somewhere on a grid over the image. Rendering, unprojection and undistorting frames need a one-to-one distortion.
const char* distortion_problem(const Camera& camera);

}  // namespace bolo::sim::scene
