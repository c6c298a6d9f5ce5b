// The named scenes: contents, temperature ranges, hot spots, moving cars, determinism.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

#include <catch2/catch.hpp>

#include "bolo/sim/scene/renderer.hpp"
#include "bolo/sim/scene/trajectory.hpp"
#include "png_writer.hpp"

using namespace bolo::sim::scene;

TEST_CASE("scenes by name, an unknown name lists the valid ones", "[scene][scenes]") {
  for (const auto& n : scene_names()) {
    const Scene s = make_scene(n, 1);
    CHECK(s.name == n);
    CHECK_NOTHROW(s.validate());
  }
  try {
    make_scene("beach", 1);
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    CHECK_THAT(m, Catch::Contains("'beach'"));
    CHECK_THAT(m, Catch::Contains("street") && Catch::Contains("lab") && Catch::Contains("checker"));
  }
}

TEST_CASE("scenes are deterministic from the seed", "[scene][scenes]") {
  const Camera cam(96, 80, 50.0);
  const Trajectory drive = make_trajectory("drive", 0);
  const auto a = Renderer(make_scene("street", 42), cam, {1, 1}).render(drive.pose(8.0), 8.0);
  const auto b = Renderer(make_scene("street", 42), cam, {2, 1}).render(drive.pose(8.0), 8.0);
  const auto c = Renderer(make_scene("street", 43), cam, {1, 1}).render(drive.pose(8.0), 8.0);
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
  CHECK(std::memcmp(a.data(), c.data(), a.size() * sizeof(float)) != 0);
}

TEST_CASE("street: temperatures of sky, road, facades, lamps, cars are physical", "[scene][scenes][street]") {
  const Scene s = make_scene("street", 7);
  const Renderer r(s, Camera(32, 32, 40.0), {1, 1});
  const Trajectory drive = make_trajectory("drive", 7);
  const Eigen::Vector3d eye = drive.pose(0.0).position;

  // Straight up: the cold zenith; 5 degrees above the horizon along the street: warmer sky.
  RayHit up = r.trace(eye, {0, 0, 1}, 0.0);
  CHECK(up.kind == RayHit::Kind::sky);
  CHECK(up.temperature_k == Approx(232.0).margin(0.5));
  RayHit low = r.trace(eye, {1, 0, std::tan(5.0 * M_PI / 180.0)}, 0.0);
  CHECK(low.kind == RayHit::Kind::sky);
  CHECK(low.temperature_k > up.temperature_k + 10.0);
  CHECK(low.temperature_k < 260.0);

  // Down onto the road a few metres ahead: asphalt ~275-280 K.
  for (double x : {5.0, 7.3, 11.0, 23.0}) {
    const RayHit road = r.trace(eye, Eigen::Vector3d(x, -2.0, 0.0) - eye + Eigen::Vector3d(0, 0.37, 0), 0.0);
    CHECK(road.kind == RayHit::Kind::quad);
    CHECK(road.point.z() == Approx(0.01));
    CHECK(road.temperature_k > 272.0);
    CHECK(road.temperature_k < 282.0);
  }

  // Every lamp: hot glass underneath (320-350 K), seen from the sidewalk below it.
  int lamps = 0;
  for (const Box& b : s.boxes) {
    const Material& m = s.materials[b.material];
    if (!std::holds_alternative<Lamp>(m.pattern)) continue;
    const Eigen::Vector3d c = b.placement * Eigen::Vector3d(0.5 * (b.lo.x() + b.hi.x()), 0.5 * (b.lo.y() + b.hi.y()), b.lo.z());
    const RayHit h = r.trace(c - Eigen::Vector3d(0, 0, 4.0), {0, 0, 1}, 0.0);
    REQUIRE(h.kind == RayHit::Kind::box);
    CHECK(h.surface.face == 5);
    CHECK(h.temperature_k >= 319.0);
    CHECK(h.temperature_k <= 350.5);
    ++lamps;
  }
  CHECK(lamps > 60);

  // Moving cars: hot grilles and exhausts (330-370 K); parked ones mostly cold.
  int moving = 0, parked = 0;
  for (const Material& m : s.materials) {
    if (const auto* c = std::get_if<CarPaint>(&m.pattern)) {
      SurfacePoint front;
      front.face = 0;
      front.p = Eigen::Vector3d(0.5 * c->length_m, 0.0, c->body_bottom_m + 0.3);
      const double engine = m.temperature_from_base(front, m.base_k);
      SurfacePoint rear;
      rear.face = 1;
      rear.p = Eigen::Vector3d(-0.5 * c->length_m, -0.5 * c->width_m + 0.4, c->body_bottom_m + 0.08);
      const double exhaust = m.temperature_from_base(rear, m.base_k);
      if (m.name == "moving car") {
        ++moving;
        CHECK(engine >= 328.0);
        CHECK(engine <= 371.0);
        CHECK(exhaust >= 328.0);
        CHECK(exhaust <= 372.0);
      } else {
        ++parked;
        CHECK(engine < 330.0);
      }
    }
  }
  CHECK(moving == 12);
  CHECK(parked > 100);

  // Facades: walls around 280-286 K, lit windows 290-300 K, dark windows colder.
  const Material* facade = nullptr;
  for (const Material& m : s.materials)
    if (std::holds_alternative<Facade>(m.pattern)) facade = &m;
  REQUIRE(facade);
  int warm = 0, samples = 0;
  double hottest = 0.0;
  for (std::uint64_t building = 1; building < 40; ++building) {
    for (double u = 0.05; u < 20.0; u += 0.1) {
      for (double v = 3.0; v < 12.0; v += 0.1) {
        SurfacePoint p;
        p.face = 2;
        p.uv = Eigen::Vector2d(u, v);
        p.face_size = Eigen::Vector2d(20.0, 16.0);
        p.object_seed = building;
        const double t = facade->temperature(p, 0.0);
        CHECK(t > 265.0);
        CHECK(t < 302.0);
        hottest = std::max(hottest, t);
        warm += t > 289.0;
        ++samples;
      }
    }
  }
  CHECK(hottest > 297.0);
  CHECK(warm > samples / 50);
  CHECK(warm < samples / 4);
}

TEST_CASE("street frames stay within 225-375 K and show hot spots", "[scene][scenes][street]") {
  const Scene s = make_scene("street", 1);
  const Camera cam(160, 128, 50.0);
  const Renderer r(s, cam);
  for (const char* name : {"drive", "handheld", "flyover", "static", "pan"}) {
    const Trajectory tr = make_trajectory(name, 1);
    float lo = 1e9f, hi = 0.0f;
    for (double t : {1.0, 9.5, 17.0, 31.0}) {
      const auto img = r.render(tr.pose(t), t);
      for (float v : img) {
        REQUIRE(std::isfinite(v));
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
    INFO(name << ": " << lo << " .. " << hi << " K");
    CHECK(lo > 225.0f);
    CHECK(hi < 375.0f);
    CHECK(hi > 300.0f);  // a lamp, a window or an engine somewhere in four frames
  }
}

TEST_CASE("street: passing cars change the static camera's image, nothing else does", "[scene][scenes][street]") {
  const Scene s = make_scene("street", 5);
  const Trajectory fixed = make_trajectory("static", 5);
  const Camera cam(96, 72, 50.0);
  const Renderer r(s, cam, {0, 1});
  const double dt = 1.0 / 60.0;
  int frames_with_cars = 0;
  for (double t = 0.0; t < 40.0; t += 0.5) {
    const auto a = r.render(fixed.pose(t), t);
    const auto b = r.render(fixed.pose(t + dt), t + dt);
    if (std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0) continue;
    ++frames_with_cars;
    if (frames_with_cars > 3) continue;
    // Every pixel that changed saw a moving car at t or t+dt.
    for (std::uint32_t y = 0; y < cam.height; ++y)
      for (std::uint32_t x = 0; x < cam.width; ++x) {
        const std::size_t i = y * cam.width + x;
        if (a[i] == b[i]) continue;
        const bool car = r.trace_pixel(fixed.pose(t), t, {double(x), double(y)}).moving ||
                         r.trace_pixel(fixed.pose(t + dt), t + dt, {double(x), double(y)}).moving;
        if (!car) FAIL("pixel " << x << "," << y << " changed without a moving car at t=" << t);
      }
  }
  INFO("frames with a passing car: " << frames_with_cars << " of 80");
  CHECK(frames_with_cars >= 4);
  CHECK(frames_with_cars < 60);
}

TEST_CASE("lab: the blackbody target fills the view and follows the schedule", "[scene][scenes][lab]") {
  const Scene lab = make_scene("lab", 0);
  const Trajectory bb = make_trajectory("blackbody", 0);
  CHECK(bb.scene() == "lab");
  const BlackbodySchedule schedule;
  const Renderer r(lab, Camera(80, 60, 57.0), {2, 1});
  int closed = 0;
  for (double t = 0.0; t < schedule.period_s() + 3.0; t += 0.37) {
    const float expected = static_cast<float>(schedule.temperature(t));
    const auto img = r.render(bb.pose(t), t);
    for (float v : img) REQUIRE(v == expected);
    closed += schedule.chopper_closed(t);
  }
  CHECK(closed > 10);
  // Plateaus step; the chopper closes on the blade in the second half of each period.
  CHECK(schedule.temperature(1.0) == 293.15);
  CHECK(schedule.temperature(11.0) == 303.15);
  CHECK(schedule.temperature(6.1) == 293.15);   // chopper open
  CHECK(schedule.temperature(6.3) == 296.15);   // closed: blade
  CHECK(schedule.temperature(6.6) == 293.15);   // open again
  CHECK(schedule.temperature(71.0) == schedule.temperature(1.0));  // periodic
  // A wide lens sees the room around the target.
  const Renderer wide(lab, Camera(80, 60, 150.0), {1, 1});
  const auto img = wide.render(bb.pose(1.0), 1.0);
  CHECK(std::count(img.begin(), img.end(), 293.15f) > 0);
  CHECK(std::count_if(img.begin(), img.end(), [](float v) { return std::abs(v - 295.0f) < 2.5f; }) > 0);
}

TEST_CASE("checker: exact two-level squares on wall and ground", "[scene][scenes]") {
  const Scene s = make_scene("checker", 0);
  const Renderer r(s, Camera(64, 48, 50.0), {1, 1});
  // The wall at x = 2.5: u = -y, v = z; square (floor(u/0.25) + floor(v/0.25)) parity.
  for (double y : {-1.3, -0.1, 0.4, 1.7}) {
    for (double z : {0.3, 1.1, 2.6}) {
      const RayHit h = r.trace({0, 0, 1.2}, Eigen::Vector3d(2.5, y, z) - Eigen::Vector3d(0, 0, 1.2), 0.0);
      const long parity = (long(std::floor(-y / 0.25)) + long(std::floor(z / 0.25))) & 1;
      CHECK(h.temperature_k == (parity ? 310.0 : 280.0));
    }
  }
  // The ground behind the camera: 1 m squares at 275/295 K.
  const RayHit g = r.trace({0, 0, 1.2}, {-1.5, 0.2, -1.2}, 0.0);
  CHECK(g.kind == RayHit::Kind::quad);
  CHECK((g.temperature_k == 275.0 || g.temperature_k == 295.0));
}

// Not run by default: writes false-colour PNGs of the scenes to look at.
//   test_scene "[.png]"   (folder: $BOLO_SCENE_PNG_DIR or the temp folder)
TEST_CASE("write PNGs of the scenes", "[.png]") {
  const char* env = std::getenv("BOLO_SCENE_PNG_DIR");
  const std::filesystem::path dir = env ? env : (std::filesystem::temp_directory_path() / "bolo-scene-png");
  std::filesystem::create_directories(dir);
  const Camera cam(320, 256, 50.0);
  struct Shot {
    const char* scene;
    const char* trajectory;
    double t;
  };
  for (const Shot sh : {Shot{"street", "drive", 0.0}, Shot{"street", "drive", 6.0}, Shot{"street", "drive", 26.0},
                        Shot{"street", "drive", 31.0}, Shot{"street", "drive", 45.0}, Shot{"street", "static", 10.0},
                        Shot{"street", "pan", 4.0}, Shot{"street", "handheld", 5.0}, Shot{"lab", "blackbody", 3.0},
                        Shot{"checker", "blackbody", 0.0}}) {
    const Renderer r(make_scene(sh.scene, 1), cam, {0, 2});
    const Trajectory tr = make_trajectory(sh.trajectory, 1);
    const auto img = r.render(tr.pose(sh.t), sh.t);
    const std::string name = std::string(sh.scene) + "-" + sh.trajectory + "-" + std::to_string(int(sh.t * 10)) + ".png";
    bolo::test::write_temperature_png(dir / name, cam.width, cam.height, img, 255.0f, 315.0f);
    const auto [lo, hi] = std::minmax_element(img.begin(), img.end());
    std::cout << (dir / name).string() << ": " << *lo << " .. " << *hi << " K\n";
  }
}
