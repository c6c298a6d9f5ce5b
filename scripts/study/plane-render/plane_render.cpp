// A recording rendered outside bolo's simulator, to check the VO on frames it was not developed
// on: one real thermal frame (a .npy stack's first frame, e.g. ../shared's FLIR T1030 clip) as the
// texture of a ground plane 3 m wide, seen from ~1.2 m by a pinhole camera looking down (hfov
// 50 deg) that moves forward at SPEED m/s with a slow sway in height, yaw, roll and pitch; one ray
// a pixel with a bilinear texture lookup, exposure at mid-frame; the paper's two-frame model
// y_i = alpha y_{i-1} + (1 - alpha) s_i with t_e = t_r = half the frame period (tau_h = tau_c =
// TAU); white noise of NOISE counts; uint16 counts. Writes the recording format (recording.json,
// frames.npy, frames.csv, camera.json, poses.tum, and truth/effects.json with tau) into OUT.
//
//   plane_render TEXTURE.npy OUT WIDTH HEIGHT FRAMES FPS TAU NOISE [SPEED]
//
// Its own code on purpose (ray-plane intersection, texture lookup, ghost, noise): nothing of
// sim/scene or sim/simulator. Built and run by scripts/study/plane-render.sh.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "plane_render: %s\n", what.c_str());
  std::exit(2);
}

struct Texture {
  int width = 0, height = 0;
  std::vector<double> texels;
  double at(double u, double v) const {  // bilinear, clamped to the edge
    u = std::clamp(u, 0.0, width - 1.001), v = std::clamp(v, 0.0, height - 1.001);
    const int x = static_cast<int>(u), y = static_cast<int>(v);
    const double a = u - x, b = v - y;
    const auto t = [&](int xx, int yy) { return texels[static_cast<std::size_t>(yy) * width + xx]; };
    return (1 - b) * ((1 - a) * t(x, y) + a * t(x + 1, y)) + b * ((1 - a) * t(x, y + 1) + a * t(x + 1, y + 1));
  }
};

// The first frame of a little-endian uint16 (N, H, W) .npy file, version 1.
Texture read_texture(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(f)), {});
  if (bytes.size() < 10 || std::string(bytes.data() + 1, 5) != "NUMPY" || bytes[6] != 1) fail(path + ": not a version 1 .npy file");
  const std::size_t header_len = static_cast<unsigned char>(bytes[8]) | static_cast<unsigned char>(bytes[9]) << 8;
  const std::string header(bytes.data() + 10, header_len);
  if (header.find("'<u2'") == std::string::npos) fail(path + ": field descr: not <u2");
  int n = 0, h = 0, w = 0;
  const std::size_t shape = header.find("'shape': (");
  if (shape == std::string::npos || std::sscanf(header.c_str() + shape + 10, "%d, %d, %d", &n, &h, &w) != 3 || n < 1 || h < 2 || w < 2)
    fail(path + ": field shape: not (N, H, W)");
  if (bytes.size() < 10 + header_len + std::size_t{2} * w * h) fail(path + ": truncated");
  Texture t{w, h, std::vector<double>(static_cast<std::size_t>(w) * h)};
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + 10 + header_len);
  for (std::size_t i = 0; i < t.texels.size(); ++i) t.texels[i] = p[2 * i] | p[2 * i + 1] << 8;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 9) fail("usage: plane_render TEXTURE.npy OUT WIDTH HEIGHT FRAMES FPS TAU NOISE [SPEED]");
  const Texture tex = read_texture(argv[1]);
  const std::filesystem::path out = argv[2];
  const int W = std::atoi(argv[3]), H = std::atoi(argv[4]), N = std::atoi(argv[5]);
  const double fps = std::atof(argv[6]), tau = std::atof(argv[7]), noise = std::atof(argv[8]);
  const double speed = argc > 9 ? std::atof(argv[9]) : 0.3;
  if (W < 16 || H < 16 || N < 3 || !(fps > 0) || !(tau > 0) || !(noise >= 0)) fail("bad size, frames, fps, tau or noise");
  const double fx = W / 2.0 / std::tan(50.0 * M_PI / 360.0), cx = (W - 1) / 2.0, cy = (H - 1) / 2.0;
  const double metres_per_texel = 3.0 / tex.width;
  // Camera x right, y down, z forward; looking down at the plane z = 0, image x along -y world.
  const auto pose = [&](double t, Eigen::Matrix3d& R, Eigen::Vector3d& C) {
    C = Eigen::Vector3d(-0.7 + speed * t, 0.05 * std::sin(1.3 * t), 1.2 + 0.05 * std::sin(0.9 * t));
    Eigen::Matrix3d down;
    down << 0, -1, 0, -1, 0, 0, 0, 0, -1;
    R = Eigen::AngleAxisd(0.09 * std::sin(1.1 * t), Eigen::Vector3d::UnitZ()).toRotationMatrix() * down *
        Eigen::AngleAxisd(0.05 * std::sin(1.7 * t + 1), Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        Eigen::AngleAxisd(0.04 * std::sin(0.7 * t), Eigen::Vector3d::UnitX()).toRotationMatrix();
  };
  const double half = 0.5 / fps, alpha = std::exp(-half / tau);
  std::vector<double> y(static_cast<std::size_t>(W) * H, 0.0);
  std::vector<std::uint16_t> frames(static_cast<std::size_t>(N) * W * H);
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, noise > 0 ? noise : 1.0);
  std::filesystem::create_directories(out);
  std::ofstream tum(out / "poses.tum");
  char line[256];
  for (int i = -30; i < N; ++i) {  // 30 frames before the first settle the ghost
    const double t = i / fps;
    Eigen::Matrix3d R;
    Eigen::Vector3d C;
    pose(t + half / 2, R, C);  // mid-exposure
    for (int r = 0; r < H; ++r)
      for (int c = 0; c < W; ++c) {
        const Eigen::Vector3d d = R * Eigen::Vector3d((c - cx) / fx, (r - cy) / fx, 1.0);
        const Eigen::Vector3d X = C + (-C.z() / d.z()) * d;
        const double s = tex.at(X.x() / metres_per_texel + tex.width / 2.0, X.y() / metres_per_texel + tex.height / 2.0);
        double& v = y[static_cast<std::size_t>(r) * W + c];
        v = i == -30 ? s : alpha * v + (1 - alpha) * s;
        if (i >= 0)
          frames[static_cast<std::size_t>(i) * W * H + static_cast<std::size_t>(r) * W + c] =
              static_cast<std::uint16_t>(std::clamp(std::lround(v + (noise > 0 ? gauss(rng) : 0.0)), 0L, 65535L));
      }
    if (i < 0) continue;
    Eigen::Quaterniond q(R);
    if (q.w() < 0) q.coeffs() *= -1;
    std::snprintf(line, sizeof line, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", t, C.x(), C.y(), C.z(), q.x(), q.y(), q.z(), q.w());
    tum << line;
  }
  std::snprintf(line, sizeof line, "{'descr': '<u2', 'fortran_order': False, 'shape': (%d, %d, %d), }", N, H, W);
  std::string header = line;
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream npy(out / "frames.npy", std::ios::binary);
  npy.write("\x93NUMPY\x01\x00", 8);
  const char len[2] = {static_cast<char>(header.size() & 0xff), static_cast<char>(header.size() >> 8)};
  npy.write(len, 2);
  npy << header;
  for (const std::uint16_t v : frames) npy.put(static_cast<char>(v & 0xff)).put(static_cast<char>(v >> 8));
  std::ofstream csv(out / "frames.csv");
  csv << "index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\n";
  for (int i = 0; i < N; ++i) {
    std::snprintf(line, sizeof line, "%d,%.9f,%.9f,%.9f,0,,\n", i, i / fps, half, half);
    csv << line;
  }
  std::ofstream(out / "recording.json") << "{\"format\": \"bolo-recording\", \"version\": 1, \"sensor\": \"plane_render\", \"width\": " << W
                                        << ", \"height\": " << H << ", \"bits\": 16, \"fps\": " << fps
                                        << ", \"units\": \"counts\", \"source\": \"scripts/study/plane-render: a real thermal frame on a plane, tau "
                                        << tau << " s, noise " << noise << " counts\"}\n";
  std::snprintf(line, sizeof line, "{\"model\": \"pinhole\", \"fx\": %.9f, \"fy\": %.9f, \"cx\": %.1f, \"cy\": %.1f, \"k1\": 0, \"k2\": 0, \"p1\": 0, \"p2\": 0}\n", fx, fx, cx, cy);
  std::ofstream(out / "camera.json") << line;
  // What bolo evaluate reads for the tau error (truth/ is evaluation-only material).
  std::filesystem::create_directories(out / "truth");
  std::snprintf(line, sizeof line, "{\"baseline\": {\"tau_h_s\": %.9f, \"tau_c_s\": %.9f}}\n", tau, tau);
  std::ofstream(out / "truth" / "effects.json") << line;
  return 0;
}
