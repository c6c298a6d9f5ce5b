// bolo-render-bench: wall time of the scene renderer (sim/scene) on 320x256 street/drive frames,
// on the calling thread and on its pool. A measurement, so a tool rather than a test case.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "bolo/sim/scene/renderer.hpp"
#include "bolo/sim/scene/trajectory.hpp"
#include "number_arg.hpp"

using namespace bolo;

constexpr const char* kUsage =
    "usage: bolo-render-bench [--frames N]\n"
    "\n"
    "Times the scene renderer on 320x256 street/drive frames (one ray per pixel), with one thread\n"
    "and with one per core: best and mean wall-clock ms per frame.\n"
    "\n"
    "  --frames N  frames per setting (default 12, at least 1)\n"
    "  --help      this text\n";

int main(int argc, char** argv) {
  int frames = 12;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--help")) {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) {
      if (!bench::parse_number_arg(argv[++i], frames, 1, std::numeric_limits<int>::max(), "bolo-render-bench", "--frames", "at least 1"))
        return 2;
    } else {
      std::fprintf(stderr, "bolo-render-bench: unknown option or missing value: %s\n%s", argv[i], kUsage);
      return 2;
    }
  }
  const sim::scene::Scene street = sim::scene::make_scene("street", 1);
  const sim::scene::Trajectory drive = sim::scene::make_trajectory("drive", 1);
  const sim::scene::Camera cam(320, 256, 50.0);
  std::vector<float> out(320 * 256);
  for (unsigned threads : {1u, 0u}) {
    const sim::scene::Renderer r(street, cam, {threads, 1});
    double best = std::numeric_limits<double>::max(), total = 0.0;
    for (int i = 0; i < frames; ++i) {
      const double t = 2.0 + 5.0 * (i % 12);  // 2..57 s, within the drive
      const auto t0 = std::chrono::steady_clock::now();
      r.render(drive.pose(t), t, out);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      best = std::min(best, ms);
      total += ms;
    }
    std::printf("scene render 320x256 street/drive, threads=%s: best %.2f ms, mean %.2f ms per frame\n",
                threads ? std::to_string(threads).c_str() : "auto", best, total / frames);
  }
  return 0;
}
