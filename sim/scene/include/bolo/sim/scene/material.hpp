#pragma once
// Procedural temperature textures. A material maps a surface point, given in the coordinates of
// the object it belongs to (so the texture moves with a moving object), to a temperature in
// kelvin:
//
//   T = pattern(base + per-object offset, point) + smooth field + fine detail
//
// where the smooth field and the detail are value noise (amplitude in K, feature size in m) in
// the face's (u, v) coordinates, and the pattern adds edges, details and hot spots (lane
// markings, tiles, windows, engines, lamps, a checkerboard).

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>

namespace bolo::sim::scene {

// Where a ray hit a surface, in the hit object's own frame.
struct SurfacePoint {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  // hit point, object frame (metres)
  // Face coordinates (metres). Box faces: from the face's lower corner, u along the first and
  // v along the second of the two in-face axes (x-faces: (y, z); y-faces: (x, z); z-faces:
  // (x, y)), so on a vertical face v is the height above the box bottom. Quads: (u, v) along the
  // quad's axes from its origin.
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  Eigen::Vector2d face_size = Eigen::Vector2d::Zero();  // extent of the face in uv (may be inf)
  int face = -1;                  // box face 0:+x 1:-x 2:+y 3:-y 4:+z 5:-z; -1 for a quad
  std::uint64_t object_seed = 0;  // per-object random variation (windows lit, heat, ...)
};

// --- patterns -------------------------------------------------------------------------------

struct Plain {};

// Checkerboard in (u, v) with two absolute temperatures (the base is ignored).
struct Checker {
  double square_m = 0.25;
  double cold_k = 280.0;
  double hot_k = 310.0;
};

// Paving tiles: joints (cooler or warmer lines) and a random offset per tile.
struct Tiles {
  double size_m = 0.6;
  double joint_m = 0.012;
  double joint_dk = -0.8;
  double tile_jitter_k = 0.4;
};

// A road surface in (u along the road, v across it, v = 0 on the centre line): dashed centre
// line, solid edge lines, warm tyre tracks in each lane, zebra crossings, repair patches.
struct RoadMarkings {
  double centre_dash_m = 3.0, centre_gap_m = 6.0;
  double line_width_m = 0.15;
  double edge_offset_m = 4.0;      // |v| of the two solid edge lines
  double paint_dk = -2.5;          // paint is a little cooler than asphalt at night
  double lane_centre_m = 2.0;      // |v| of the lane centres (tyre tracks at +-0.8 m of it)
  double track_dk = 0.6;
  double patch_dk = 1.0;           // amplitude of repair patches (one chance per 10 m cell)
  std::vector<std::pair<double, double>> gaps;  // u ranges with no markings (junctions)
  std::vector<double> crosswalks;  // u centres of 4 m wide zebra crossings
  double crosswalk_half_width_m = 6.0;  // |v| extent of the zebra stripes
};

// Building: window grid on the vertical faces, floor slabs, shop fronts, cold roof.
// Window geometry varies per building (object_seed) within the given ranges.
struct Facade {
  double floor_height_min_m = 2.9, floor_height_max_m = 3.4;
  double window_spacing_min_m = 2.6, window_spacing_max_m = 3.6;
  double window_width_m = 1.2, window_height_m = 1.5, sill_m = 0.9;
  double lit_fraction = 0.55;                   // warm windows (heated rooms)
  double lit_min_k = 290.0, lit_max_k = 300.0;
  double dark_min_k = 270.0, dark_max_k = 277.0;  // glass mirroring the cold sky
  double frame_dk = 2.5;                        // window frames: thermal bridges
  double slab_dk = 1.5;                         // floor slabs
  double shop_probability = 0.5;                // lit shop front on the ground floor
  double shop_min_k = 294.0, shop_max_k = 300.0;
  double roof_k = 268.0;                        // +z face: radiative cooling
};

// A car in its own frame: x forward, y left, z up, origin on the ground under its centre. Body
// box [-L/2, L/2] x [-W/2, W/2] x [body_bottom, body_top], cabin box on top of it up to
// cabin_top from x = cabin_rear to x = cabin_front. `heat` in [0, 1] scales the engine, hood,
// exhaust, brake and tyre temperatures from the paint temperature (0: parked for hours).
struct CarPaint {
  double length_m = 4.4, width_m = 1.8;
  double body_bottom_m = 0.12, body_top_m = 0.95, cabin_top_m = 1.45;
  double cabin_rear_m = -1.3, cabin_front_m = 0.8;
  double wheelbase_m = 2.7, wheel_radius_m = 0.33;
  double heat = 1.0;
  double engine_k = 360.0;   // radiator grille / engine bay at full heat
  double exhaust_k = 365.0;  // tail pipe at full heat
  double hood_k = 320.0;
  double tyre_k = 308.0;
  double glass_k = 269.0;    // windows mirror the sky
};

// A street lamp head: hot glass on its underside (-z face), Gaussian around the face centre.
struct Lamp {
  double peak_k = 335.0;
  double housing_k = 300.0;
  double radius_m = 0.15;  // 1/e radius of the hot spot
};

using Pattern = std::variant<Plain, Checker, Tiles, RoadMarkings, Facade, CarPaint, Lamp>;

struct Material {
  std::string name;
  double base_k = 280.0;
  // Optional time dependence of the base (e.g. a blackbody schedule); overrides base_k.
  std::function<double(double t)> base_of_t;
  double object_jitter_k = 0.0;  // uniform random offset per object, +-this
  double noise_k = 0.0, noise_scale_m = 2.0;     // smooth field
  double detail_k = 0.0, detail_scale_m = 0.2;   // fine texture
  Pattern pattern = Plain{};
  std::uint64_t seed = 0;

  double base_at(double t) const { return base_of_t ? base_of_t(t) : base_k; }
  // Temperature (K) at a surface point at time t.
  double temperature(const SurfacePoint& s, double t) const {
    return temperature_from_base(s, base_at(t));
  }
  // The same with the (possibly time-dependent) base already evaluated.
  double temperature_from_base(const SurfacePoint& s, double base) const;
};

}  // namespace bolo::sim::scene
