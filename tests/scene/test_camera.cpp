#include <algorithm>
#include <cmath>
#include <string>

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

namespace {

// The Optris PI450's calibration in ../shared/data/real/optris-pi450-handheld/camera.json
// (cv::calibrateCamera's rational model, 382 x 288).
Camera optris_pi450() {
  Camera c;
  c.width = 382, c.height = 288;
  c.fx = 377.32227553759276, c.fy = 378.27518590799593;
  c.cx = 190.98670415464665, c.cy = 148.90328824683087;
  c.k1 = -0.19666214082095448, c.k2 = -1.8316527667010765;
  c.p1 = 4.14886277407486e-05, c.p2 = -0.0004457029653203337;
  c.k3 = 5.431916500757228, c.k4 = 0.2761986355556445, c.k5 = -2.4816640836747377, c.k6 = 6.667848761560231;
  return c;
}

}  // namespace

TEST_CASE("rational distortion: points computed outside this code", "[scene][camera]") {
  const Camera c = optris_pi450();
  // Off the axes, every term at work: OpenCV's formula evaluated by `bc -l` at 30 digits.
  const auto off_axis = c.project({0.3, -0.2, 1.0});
  REQUIRE(off_axis);
  CHECK(off_axis->x() == Approx(298.158517254606244856).margin(1e-9));
  CHECK(off_axis->y() == Approx(77.262402839952014802).margin(1e-9));
  // On the x axis (y = 0) the formula is, in closed form,
  //   xd = x (1 + k1 x^2 + k2 x^4 + k3 x^6) / (1 + k4 x^2 + k5 x^4 + k6 x^6) + 3 p2 x^2,  yd = p1 x^2.
  for (const double x : {-0.6, -0.25, 0.1, 0.45, 0.7}) {
    const double x2 = x * x;
    const double radial = (1 + c.k1 * x2 + c.k2 * x2 * x2 + c.k3 * x2 * x2 * x2) /
                          (1 + c.k4 * x2 + c.k5 * x2 * x2 + c.k6 * x2 * x2 * x2);
    const Eigen::Vector2d d = c.distort({x, 0.0});
    CHECK(d.x() == Approx(x * radial + 3 * c.p2 * x2).margin(1e-15));
    CHECK(d.y() == Approx(c.p1 * x2).margin(1e-15));
  }
  // The denominator matters: the numerator alone puts the same point elsewhere by pixels.
  Camera numerator_only = c;
  numerator_only.k4 = numerator_only.k5 = numerator_only.k6 = 0;
  CHECK((*numerator_only.project({0.3, -0.2, 1.0}) - *off_axis).norm() > 1.0);
}

TEST_CASE("rational distortion: undistort inverts distort over the Optris image (< 1e-6 px)", "[scene][camera]") {
  const Camera c = optris_pi450();
  REQUIRE(bolo::sim::scene::distortion_problem(c) == nullptr);
  double worst = 0.0;
  for (double v = -0.5; v <= 287.5; v += 0.5)
    for (double u = -0.5; u <= 381.5; u += 0.5) {
      const Eigen::Vector2d d((u - c.cx) / c.fx, (v - c.cy) / c.fy);
      const Eigen::Vector2d back = c.distort(c.undistort(d));
      worst = std::max(worst, std::hypot(c.fx * (back.x() - d.x()), c.fy * (back.y() - d.y())));
    }
  INFO("worst " << worst << " px");
  CHECK(worst < 1e-6);
}

TEST_CASE("rational distortion: camera.json's k3..k6, and lenses that cannot be inverted", "[scene][camera]") {
  const Camera c = optris_pi450();
  const nlohmann::json j = c.to_json();
  CHECK(j.size() == 13);
  CHECK(j.at("k6").get<double>() == c.k6);
  nlohmann::json written = j;
  written["distortion_model"] = "opencv-rational (k1 k2 p1 p2 k3 k4 k5 k6)";  // as OpenCV tools note it
  const Camera back = Camera::from_json(nlohmann::json::parse(written.dump()), 382, 288);
  CHECK(back.k3 == c.k3);
  CHECK(back.k4 == c.k4);
  CHECK(back.k5 == c.k5);
  CHECK(back.k6 == c.k6);
  CHECK(back.distorted());
  CHECK_FALSE(Camera(382, 288, 50.0).distorted());
  CHECK(Camera(382, 288, 50.0).to_json().size() == 9);  // Brown-Conrady files stay as they were
  CHECK_THROWS_WITH(Camera::from_json(nlohmann::json::parse(R"({"fx":100,"fy":100,"cx":1,"cy":2,"k5":"x"})"), 4, 4),
                    Catch::Contains("field k5 is not a number"));
  // The Optris lens read as Brown-Conrady only (k3..k6 dropped) folds inside the image.
  Camera truncated = c;
  truncated.k3 = truncated.k4 = truncated.k5 = truncated.k6 = 0;
  REQUIRE(bolo::sim::scene::distortion_problem(truncated) != nullptr);
  CHECK(std::string(bolo::sim::scene::distortion_problem(truncated)).find("folds back") != std::string::npos);
}
