// Renderer geometry and physics on small hand-built scenes.
#include <cmath>
#include <cstring>

#include <catch2/catch.hpp>

#include "bolo/sim/scene/renderer.hpp"
#include "bolo/sim/scene/trajectory.hpp"

using namespace bolo::sim::scene;

namespace {

// An infinite wall x = 6 (u to the viewer's right = -y, v up), textured; a tiled ground.
Scene wall_scene() {
  Scene s;
  s.name = "wall";
  Material wall;
  wall.name = "wall";
  wall.base_k = 290.0;
  wall.noise_k = 3.0;
  wall.noise_scale_m = 0.7;
  wall.detail_k = 0.5;
  wall.detail_scale_m = 0.05;
  wall.pattern = Tiles{0.4, 0.02, -2.0, 1.0};
  wall.seed = 11;
  const std::size_t wm = s.add_material(wall);
  Material ground;
  ground.base_k = 280.0;
  const std::size_t gm = s.add_material(ground);
  Quad w;
  w.origin = Eigen::Vector3d(6.0, 0.0, 0.0);
  w.u_axis = -Eigen::Vector3d::UnitY();
  w.v_axis = Eigen::Vector3d::UnitZ();
  w.material = wm;
  w.seed = 5;
  s.add_quad(w);
  Quad g;
  g.material = gm;
  s.add_quad(g);
  return s;
}

Camera distorted_camera(std::uint32_t w, std::uint32_t h) {
  Camera c(w, h, 60.0);
  c.k1 = -0.18;
  c.k2 = 0.03;
  c.p1 = 0.0008;
  c.p2 = -0.0005;
  return c;
}

}  // namespace

TEST_CASE("a pixel looking at a known plane point gets that material's temperature", "[scene][render]") {
  const Scene scene = wall_scene();
  const Camera cam = distorted_camera(96, 72);
  const Renderer r(scene, cam, {1, 1});
  const Pose pose = look_at({0.0, 0.3, 1.5}, {6.0, -0.4, 2.0});
  const std::vector<float> img = r.render(pose, 0.0);
  const Eigen::Matrix3d rot = pose.orientation.toRotationMatrix();
  int checked = 0;
  for (std::uint32_t y = 0; y < cam.height; y += 5) {
    for (std::uint32_t x = 0; x < cam.width; x += 7) {
      // Independent geometry: the pixel's ray meets the plane x = 6 at P.
      const Eigen::Vector3d d = rot * cam.unproject({double(x), double(y)});
      if (d.x() <= 0.0) continue;
      const double t = (6.0 - pose.position.x()) / d.x();
      const Eigen::Vector3d p = pose.position + t * d;
      if (p.z() <= 0.0) continue;  // the ground is nearer
      SurfacePoint sp;
      sp.uv = Eigen::Vector2d(-p.y(), p.z());
      sp.p = Eigen::Vector3d(sp.uv.x(), sp.uv.y(), 0.0);
      sp.object_seed = 5;
      const double expected = scene.materials[0].temperature(sp, 0.0);
      INFO("pixel " << x << "," << y << " world point " << p.transpose());
      CHECK(img[y * cam.width + x] == Approx(expected).margin(1e-3));
      // And the point itself: project P back to the pixel.
      const auto px = cam.project(pose.to_camera(p));
      REQUIRE(px);
      CHECK((*px - Eigen::Vector2d(x, y)).norm() < 1e-6);
      ++checked;
    }
  }
  CHECK(checked > 100);
}

TEST_CASE("a uniform surface renders at exactly its temperature, a textured one is not flat", "[scene][render]") {
  Scene s;
  Material m;
  m.base_k = 301.25;
  s.add_material(m);
  Quad q;
  q.origin = Eigen::Vector3d(0, 0, 0);
  s.add_quad(q);
  const Renderer r(s, Camera(64, 48, 40.0), {2, 1});
  const auto img = r.render(camera_pose({0, 0, 2.0}, 0.0, -45.0 * M_PI / 180.0), 0.0);
  for (float v : img) REQUIRE(v == 301.25f);

  const Renderer rw(wall_scene(), Camera(64, 48, 40.0), {1, 1});
  const auto tex = rw.render(look_at({0, 0, 1.5}, {6, 0, 1.5}), 0.0);
  const auto [lo, hi] = std::minmax_element(tex.begin(), tex.end());
  CHECK(*hi - *lo > 3.0);  // tiles, joints and noise
}

TEST_CASE("box faces: face index, face coordinates and the nearest hit", "[scene][render]") {
  Scene s;
  Material m;
  m.base_k = 300.0;
  m.pattern = Checker{0.5, 270.0, 320.0};
  const std::size_t mat = s.add_material(m);
  Box b;
  b.lo = Eigen::Vector3d(0, 0, 0);
  b.hi = Eigen::Vector3d(2, 3, 4);
  b.placement.translation() = Eigen::Vector3d(10, -1, 0);
  b.material = mat;
  s.add_box(b);
  Box near = b;  // a second box in front of the first hides part of it
  near.hi = Eigen::Vector3d(0.5, 0.5, 0.5);
  near.placement.translation() = Eigen::Vector3d(5, 0, 1);
  s.add_box(near);
  const Renderer r(s, Camera(32, 32, 30.0), {1, 1});
  // Along +x towards the -x face of the big box at height 1.2, y = 0.7 -> face uv (y-lo, z-lo).
  RayHit h = r.trace({0, 0.7, 1.2}, {1, 0, 0}, 0.0);
  CHECK(h.kind == RayHit::Kind::box);
  CHECK(h.index == 0);
  CHECK(h.surface.face == 1);
  CHECK(h.distance == Approx(10.0));
  CHECK(h.surface.uv.x() == Approx(1.7));
  CHECK(h.surface.uv.y() == Approx(1.2));
  CHECK(h.surface.face_size.x() == Approx(3.0));
  CHECK(h.surface.face_size.y() == Approx(4.0));
  CHECK(h.temperature_k == 320.0);  // square (3, 2): odd -> hot
  // Through the small box first.
  h = r.trace({0, 0.25, 1.25}, {1, 0, 0}, 0.0);
  CHECK(h.index == 1);
  CHECK(h.distance == Approx(5.0));
  // From above onto the top face (+z).
  h = r.trace({11, 0.5, 20}, {0, 0, -1}, 0.0);
  CHECK(h.surface.face == 4);
  CHECK(h.point.z() == Approx(4.0));
  // Missing everything: the sky.
  h = r.trace({0, 0, 1}, {-1, 0, 0.2}, 0.0);
  CHECK(h.kind == RayHit::Kind::sky);
}

TEST_CASE("rays above the horizon see the cold sky, warmer towards the horizon", "[scene][render]") {
  Scene s = wall_scene();
  s.quads.erase(s.quads.begin());  // only the ground
  const Camera cam(80, 60, 50.0);
  const Renderer r(s, cam, {1, 1});
  const Pose pose = camera_pose({0, 0, 1.5}, 0.3, 20.0 * M_PI / 180.0);  // looking up
  const auto img = r.render(pose, 0.0);
  const Eigen::Matrix3d rot = pose.orientation.toRotationMatrix();
  for (std::uint32_t y = 0; y < cam.height; ++y) {
    const Eigen::Vector3d d = rot * cam.unproject({40.0, double(y)});
    if (d.z() <= 0.0) continue;
    CHECK(img[y * cam.width + 40] == Approx(s.sky.temperature(d)).margin(1e-4));
  }
  // Top row (highest elevation) colder than the lowest sky row.
  CHECK(img[40] < img[(cam.height - 1) * cam.width + 40]);
  CHECK(s.sky.temperature({0, 0, 1}) == Approx(232.0).margin(0.3));
  CHECK(s.sky.temperature({1, 0, 1e-6}) == Approx(258.0).margin(0.01));
  for (float v : img) {
    CHECK(v >= 230.0f);
    CHECK(v <= 280.0f);
  }
}

TEST_CASE("the atmosphere mixes distant surfaces towards the air temperature", "[scene][render]") {
  Scene s;
  Material m;
  m.base_k = 320.0;
  s.add_material(m);
  Quad far;
  far.origin = Eigen::Vector3d(1000, 0, 0);
  far.u_axis = Eigen::Vector3d::UnitY();
  far.v_axis = Eigen::Vector3d::UnitZ();
  s.add_quad(far);
  s.atmosphere = {280.0, 1500.0};
  const Renderer r(s, Camera(8, 8, 10.0), {1, 1});
  const RayHit h = r.trace({0, 0, 1}, {1, 0.1, 0}, 0.0);
  CHECK(h.surface_k == 320.0);
  CHECK(h.temperature_k == Approx(280.0 + 40.0 * std::exp(-h.distance / 1500.0)).epsilon(1e-12));
  CHECK(h.distance == Approx(std::hypot(1000.0, 100.0)));
}

TEST_CASE("a moving box changes the image between t and t+dt, the static background stays identical",
          "[scene][render]") {
  Scene s = wall_scene();
  Material car;
  car.base_k = 278.0;
  car.pattern = CarPaint{};
  const std::size_t cm = s.add_material(car);
  // Drives along -y (to the viewer's right... left), 10 m/s, in front of the wall.
  const int motion = s.add_motion([](double t) {
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    m.translation() = Eigen::Vector3d(4.0, 3.0 - 10.0 * t, 0.0);
    m.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return m;
  });
  Box body;
  body.lo = Eigen::Vector3d(-2.2, -0.9, 0.12);
  body.hi = Eigen::Vector3d(2.2, 0.9, 0.95);
  body.material = cm;
  body.motion = motion;
  s.add_box(body);
  const Camera cam(120, 90, 70.0);
  const Renderer r(s, cam, {2, 1});
  const Pose pose = look_at({0, 0, 1.2}, {6, 0, 0.8});
  const double t0 = 0.3, dt = 1.0 / 120.0;
  const auto a = r.render(pose, t0);
  const auto b = r.render(pose, t0 + dt);
  int changed = 0, background = 0;
  for (std::uint32_t y = 0; y < cam.height; ++y) {
    for (std::uint32_t x = 0; x < cam.width; ++x) {
      const std::size_t i = y * cam.width + x;
      const RayHit ha = r.trace_pixel(pose, t0, {double(x), double(y)});
      const RayHit hb = r.trace_pixel(pose, t0 + dt, {double(x), double(y)});
      CHECK(ha.temperature_k == Approx(a[i]).margin(1e-3));  // trace_pixel agrees with render
      if (!ha.moving && !hb.moving) {
        ++background;
        if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0) FAIL("background pixel " << x << "," << y << " changed");
      }
      if (a[i] != b[i]) ++changed;
    }
  }
  CHECK(changed > 50);
  CHECK(background > static_cast<int>(cam.width * cam.height / 2));

  // The texture moves with the car: the same object-frame point has the same temperature.
  const Eigen::Vector3d p_obj(1.0, -0.9, 0.5);  // on the car's right side (-y face)
  for (double t : {0.25, 0.35}) {
    const Eigen::Vector3d pw = s.box_to_world(s.boxes.back(), t) * p_obj;
    const Eigen::Vector3d from = pw + Eigen::Vector3d(-3.0, 0.0, 0.0);
    const RayHit h = r.trace(from, pw - from, t);
    REQUIRE(h.moving);
    CHECK((h.surface.p - p_obj).norm() < 1e-9);
    CHECK(h.surface_k == Approx(s.materials[cm].temperature(h.surface, t)));
  }
}

TEST_CASE("render: thread count and repeated calls give bit-identical frames", "[scene][render]") {
  const Scene street = make_scene("street", 3);
  const Trajectory drive = make_trajectory("drive", 3);
  const Camera cam(160, 128, 50.0);
  std::vector<float> ref;
  for (unsigned threads : {1u, 2u, 3u, 7u}) {
    const Renderer r(street, cam, {threads, 1});
    const auto img = r.render(drive.pose(12.3), 12.3);
    if (ref.empty())
      ref = img;
    else
      CHECK(std::memcmp(ref.data(), img.data(), ref.size() * sizeof(float)) == 0);
    CHECK(std::memcmp(ref.data(), r.render(drive.pose(12.3), 12.3).data(), ref.size() * sizeof(float)) == 0);
  }
  std::vector<float> wrong(10);
  const Renderer r(street, cam);
  CHECK_THROWS_AS(r.render(drive.pose(0), 0.0, wrong), std::invalid_argument);
}

TEST_CASE("supersampling averages sub-pixel rays", "[scene][render]") {
  const Scene s = make_scene("checker", 0);
  const Camera cam(64, 48, 50.0);
  const Pose pose = camera_pose(s.viewpoint, s.viewpoint_yaw, 0.0);
  const auto one = Renderer(s, cam, {1, 1}).render(pose, 0.0);
  const auto four = Renderer(s, cam, {1, 4}).render(pose, 0.0);
  int between = 0;
  for (std::size_t i = 0; i < one.size(); ++i)
    if (four[i] > 280.5f && four[i] < 309.5f && four[i] != 295.0f) ++between;
  CHECK(between > 20);  // edge pixels are mixtures
  for (float v : one) CHECK((v == 280.0f || v == 310.0f || v == 275.0f || v == 295.0f || v < 262.0f));
}

namespace {

// Pixels where the tiled render of `street` along `trajectory` at time t differs from tracing the
// pixel's ray on its own, through a lens with distortion.
int tiled_render_mismatches(const Scene& street, const char* trajectory, double t) {
  Camera cam(120, 96, 64.0);
  cam.k1 = -0.2;
  cam.k2 = 0.04;
  cam.p1 = 0.001;
  const Renderer r(street, cam, {2, 1});
  const Pose pose = make_trajectory(trajectory, 11).pose(t);
  const auto img = r.render(pose, t);
  int mismatches = 0;
  for (std::uint32_t y = 0; y < cam.height; ++y)
    for (std::uint32_t x = 0; x < cam.width; ++x) {
      const double traced = r.trace_pixel(pose, t, {double(x), double(y)}).temperature_k;
      if (std::abs(traced - img[y * cam.width + x]) > 1e-3) ++mismatches;
    }
  return mismatches;
}

}  // namespace

TEST_CASE("the tiled renderer and per-ray tracing agree along every trajectory on the street", "[scene][render][long]") {
  const Scene street = make_scene("street", 11);
  for (const char* name : {"drive", "handheld", "pan"})
    for (double t : {3.0, 29.5}) {
      INFO(name << " t=" << t);
      CHECK(tiled_render_mismatches(street, name, t) == 0);
    }
}

TEST_CASE("the tiled renderer and per-ray tracing agree on the street (distortion, supersampling)",
          "[scene][render]") {
  const Scene street = make_scene("street", 11);
  CHECK(tiled_render_mismatches(street, "drive", 3.0) == 0);
  // Supersampling: the mean of the sub-pixel rays.
  const Camera cam(40, 32, 50.0);
  const Renderer r4(street, cam, {1, 3});
  const Renderer r1(street, cam, {1, 1});
  const Trajectory d = make_trajectory("drive", 11);
  const auto img = r4.render(d.pose(5.0), 5.0);
  for (std::uint32_t y = 0; y < cam.height; y += 3)
    for (std::uint32_t x = 0; x < cam.width; x += 3) {
      double acc = 0.0;
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          acc += r1.trace_pixel(d.pose(5.0), 5.0, {x + (i + 0.5) / 3.0 - 0.5, y + (j + 0.5) / 3.0 - 0.5}).temperature_k;
      CHECK(img[y * cam.width + x] == Approx(acc / 9.0).margin(1e-3));
    }
}
