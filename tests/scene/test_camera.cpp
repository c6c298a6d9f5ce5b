#include <cmath>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "bolo/sim/scene/camera.hpp"

using bolo::sim::scene::Camera;

TEST_CASE("camera from a horizontal field of view: square pixels, centred principal point", "[scene][camera]") {
  const Camera c(320, 256, 50.0);
  CHECK(c.fx == Approx(160.0 / std::tan(25.0 * M_PI / 180.0)).epsilon(1e-12));
  CHECK(c.fy == c.fx);
  CHECK(c.cx == 159.5);
  CHECK(c.cy == 127.5);
  CHECK(c.hfov_deg() == Approx(50.0).epsilon(1e-12));
  // The left edge of the image (u = -0.5) is at 25 degrees from the axis.
  const Eigen::Vector3d left = c.unproject({-0.5, c.cy});
  CHECK(std::atan2(-left.x(), left.z()) * 180.0 / M_PI == Approx(25.0).epsilon(1e-12));
  CHECK_THROWS_AS(Camera(0, 10, 50.0), std::invalid_argument);
  CHECK_THROWS_AS(Camera(10, 10, 180.0), std::invalid_argument);
}

TEST_CASE("camera axes: x right, y down, z forward", "[scene][camera]") {
  const Camera c(100, 80, 60.0);
  const auto right = c.project({1.0, 0.0, 5.0});
  const auto below = c.project({0.0, 1.0, 5.0});
  REQUIRE(right);
  REQUIRE(below);
  CHECK(right->x() > c.cx);
  CHECK(right->y() == Approx(c.cy));
  CHECK(below->y() > c.cy);
  CHECK_FALSE(c.project({0.0, 0.0, -1.0}));
  CHECK_FALSE(c.project({1.0, 0.0, 0.0}));
}

TEST_CASE("camera.json: exactly the recording format's object, and back", "[scene][camera]") {
  Camera c(160, 120, 57.0);
  c.k1 = -0.21;
  c.k2 = 0.05;
  c.p1 = 0.001;
  c.p2 = -0.0007;
  const nlohmann::json j = c.to_json();
  CHECK(j.size() == 9);
  CHECK(j.at("model") == "pinhole");
  CHECK(j.at("fx").get<double>() == c.fx);
  CHECK(j.at("fy").get<double>() == c.fy);
  CHECK(j.at("cx").get<double>() == 79.5);
  CHECK(j.at("cy").get<double>() == 59.5);
  CHECK(j.at("k1").get<double>() == -0.21);
  CHECK(j.at("k2").get<double>() == 0.05);
  CHECK(j.at("p1").get<double>() == 0.001);
  CHECK(j.at("p2").get<double>() == -0.0007);
  // Through text, as it would be written to camera.json.
  const Camera back = Camera::from_json(nlohmann::json::parse(j.dump()), 160, 120);
  CHECK(back.fx == c.fx);
  CHECK(back.k1 == c.k1);
  CHECK(back.p2 == c.p2);
  CHECK(back.width == 160);
  // Distortion keys are optional, and so is the model (the format has one); intrinsics are not.
  const Camera plain = Camera::from_json(nlohmann::json::parse(R"({"model":"pinhole","fx":100,"fy":100,"cx":1,"cy":2})"), 4, 4);
  CHECK(plain.k1 == 0.0);
  const Camera unnamed = Camera::from_json(nlohmann::json::parse(R"({"fx":100,"fy":90,"cx":1,"cy":2})"), 4, 4);
  CHECK(unnamed.fy == 90.0);
  CHECK_THROWS_WITH(Camera::from_json(nlohmann::json::parse(R"({"fx":-1,"fy":100,"cx":1,"cy":2})"), 4, 4),
                    Catch::Contains("fx, fy must be positive"));
  CHECK_THROWS_WITH(Camera::from_json(nlohmann::json::parse(R"({"fx":"100","fy":100,"cx":1,"cy":2})"), 4, 4),
                    Catch::Contains("field fx is not a number"));
  CHECK_THROWS_WITH(Camera::from_json(nlohmann::json::parse(R"({"model":"pinhole","fx":100,"fy":100,"cx":1})"), 4, 4),
                    Catch::Contains("cy"));
  CHECK_THROWS_WITH(Camera::from_json(nlohmann::json::parse(R"({"model":"fisheye","fx":1,"fy":1,"cx":1,"cy":1})"), 4, 4),
                    Catch::Contains("model"));
}

TEST_CASE("projection and unprojection round-trip with distortion (< 1e-6 px)", "[scene][camera]") {
  struct Dist {
    double k1, k2, p1, p2;
  };
  for (const Dist d : {Dist{0, 0, 0, 0}, Dist{-0.25, 0.08, 0.001, -0.0015}, Dist{0.15, -0.02, -0.002, 0.001},
                       Dist{-0.35, 0.12, 0.0, 0.0}}) {
    Camera c(320, 256, 56.0);
    c.fy = c.fx * 1.01;
    c.cx = 161.3;
    c.cy = 125.9;
    c.k1 = d.k1;
    c.k2 = d.k2;
    c.p1 = d.p1;
    c.p2 = d.p2;
    double worst = 0.0;
    for (double v = -0.5; v <= 255.5; v += 4.25) {
      for (double u = -0.5; u <= 319.5; u += 3.75) {
        const Eigen::Vector3d ray = c.unproject({u, v});
        CHECK(ray.norm() == Approx(1.0).epsilon(1e-12));
        // Any point along the ray projects back onto the pixel.
        const auto px = c.project(ray * 7.3);
        REQUIRE(px);
        worst = std::max(worst, (*px - Eigen::Vector2d(u, v)).norm());
      }
    }
    INFO("k1=" << d.k1 << " k2=" << d.k2 << " p1=" << d.p1 << " p2=" << d.p2 << " worst " << worst << " px");
    CHECK(worst < 1e-6);
    // And the other way: a 3D point -> pixel -> ray points at it.
    const Eigen::Vector3d p(0.8, -0.5, 3.0);
    const auto px = c.project(p);
    REQUIRE(px);
    CHECK((c.unproject(*px) - p.normalized()).norm() < 1e-9);
  }
}

TEST_CASE("barrel distortion pulls the image edge inwards", "[scene][camera]") {
  Camera c(320, 256, 60.0);
  const auto undistorted = c.project({1.0, 0.0, 2.0});
  c.k1 = -0.2;
  const auto barrel = c.project({1.0, 0.0, 2.0});
  REQUIRE(undistorted);
  REQUIRE(barrel);
  CHECK(barrel->x() < undistorted->x());
  CHECK(barrel->x() > c.cx);
}
