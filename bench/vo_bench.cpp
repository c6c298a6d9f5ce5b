// bolo-vo-bench: speed and memory of the VO core (firmware/vo) on rendered street/drive frames
// at 160x120, 320x256 and 640x512, 60 Hz, tau 12 ms through the two-frame bolometer model.
// Prints frames per second on one core, the real-time factor at 60 Hz, the arena size, the
// process's peak resident memory and the heap allocations made while frames are processed (none:
// all VO memory is the arena, allocated before the first frame). Resident memory still grows a
// little during the first size's frames, as code, stack and dynamic-linking pages (the lazily
// bound symbol table, copied on write) are touched the first time; that growth is printed split
// into file-backed and anonymous pages.
// A frame that the VO tracks costs more than one it initialises on or loses, so how many frames
// were posed moves the average: the CPU time of the posed frames alone is printed too (ms/posed),
// with the number of keyframes (each runs the window bundle adjustment).
//
//   bolo-vo-bench [--frames N] [--mode none|affine|ir] [--sizes WxH,...] [--max-keyframes N] [--carry-coring K] [--smoothing N]
//   bolo-vo-bench --write-frames FILE [--frames N] [--sizes WxH]   the first size's frames to FILE
//                                                                   (bolo-board-count vo reads it)

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/sim/scene/renderer.hpp"
#include "bolo/sim/scene/trajectory.hpp"
#include "bolo/vo/odometry.hpp"
#include "number_arg.hpp"
#if __has_include("counting_allocator.hpp")
#include "counting_allocator.hpp"
#endif
#if defined(BOLO_COUNTING_ALLOCATOR_ACTIVE) && BOLO_COUNTING_ALLOCATOR_ACTIVE
#define BOLO_VO_BENCH_COUNTS_ALLOCATIONS 1
#else
#define BOLO_VO_BENCH_COUNTS_ALLOCATIONS 0
#endif
#include "size_list.hpp"
#include "vo_frames_file.hpp"

namespace {

using namespace bolo;

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Fields of /proc/self/status, in KiB: the peak resident size, and the resident anonymous and
// file-backed pages now.
struct Resident {
  long peak = -1, anonymous = -1, file = -1;
};
Resident resident_kib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  Resident r;
  const auto field = [&](const char* name, long& value) {
    if (line.rfind(name, 0) == 0) value = std::stol(line.substr(std::strlen(name)));
  };
  while (std::getline(status, line)) field("VmHWM:", r.peak), field("RssAnon:", r.anonymous), field("RssFile:", r.file);
  return r;
}

// Adds the heap allocations (malloc, calloc, realloc, operator new) made by `work` to `total`;
// where the counting allocator is not linked or a sanitizer owns malloc, `total` is -1, "not counted".
template <typename Work>
void count_allocations(long& total, Work&& work) {
#if BOLO_VO_BENCH_COUNTS_ALLOCATIONS
  const long before = test::g_allocations.load();
  test::g_counting = true;
  work();
  test::g_counting = false;
  total += test::g_allocations.load() - before;
#else
  work();
  total = -1;
#endif
}

struct Frames {
  std::vector<std::vector<std::uint16_t>> raw;
  vo::Camera camera;
};

// Street/drive through y_i = a y_{i-1} + b u_i (tau 12 ms, t_e = t_r = half a period).
Frames render(std::uint32_t w, std::uint32_t h, int count, double fps) {
  sim::scene::Camera cam(w, h, 50.0);
  sim::scene::Renderer renderer(sim::scene::make_scene("street", 1), cam);
  const auto trajectory = sim::scene::make_trajectory("drive", 1);
  const double te = 0.5 / fps, a = std::exp(-te / 0.012), b = 1 - a;
  Frames f;
  const auto j = cam.to_json();
  f.camera = {j.at("fx").get<float>(), j.at("fy").get<float>(), j.at("cx").get<float>(), j.at("cy").get<float>()};
  std::vector<double> y;
  for (int i = 0; i < count; ++i) {
    const double t = 2.0 + i / fps;
    const auto k = renderer.render(trajectory.pose(t), t);
    if (y.empty()) y.assign(k.size(), 0.0), std::transform(k.begin(), k.end(), y.begin(), [](float v) { return 8000.0 + 40.0 * (v - 300.0); });
    std::vector<std::uint16_t> frame(k.size());
    for (std::size_t p = 0; p < k.size(); ++p) {
      y[p] = a * y[p] + b * (8000.0 + 40.0 * (k[p] - 300.0));
      frame[p] = static_cast<std::uint16_t>(std::lround(y[p]));
    }
    f.raw.push_back(std::move(frame));
  }
  return f;
}

}  // namespace

constexpr const char* kUsage =
    "usage: bolo-vo-bench [--frames N] [--mode none|affine|ir] [--sizes WxH[,WxH...]] [--max-keyframes N]\n"
    "                     [--carry-coring K] [--smoothing N] [--write-frames FILE]\n"
    "\n"
    "Times the VO core (firmware/vo) on one core over street/drive frames rendered through the\n"
    "two-frame bolometer model (60 Hz, tau 12 ms): CPU ms per frame and per posed frame, the\n"
    "real-time factor at 60 Hz, the arena size and the process's peak resident memory (which must\n"
    "not grow while frames are processed).\n"
    "\n"
    "  --frames N         frames per size (default 120, at least 10)\n"
    "  --mode M           photometric model (default ir)\n"
    "  --sizes LIST       frame sizes (default 160x120,320x256,640x512)\n"
    "  --max-keyframes N  sliding-window size, 2..8 (default 8, the VO's default)\n"
    "  --carry-coring K   ir: the carry-over correction's coring, 0..100 (default 1, the VO's default)\n"
    "  --smoothing N      binomial low-pass passes on each tracking image, 0..3 (default 1, the VO's default)\n"
    "  --write-frames F   write the first size's rendered frames and camera to F and stop (no timing):\n"
    "                     the input of bolo-board-count vo on a board or under qemu-user\n"
    "  --help             this text\n";

int main(int argc, char** argv) {
  int frames = 120;
  std::uint32_t max_keyframes = vo::VoConfig{}.max_keyframes;
  std::string mode_name = "ir";
  float carry_coring = vo::VoConfig{}.carry_coring;
  std::uint32_t smoothing = vo::VoConfig{}.smoothing;
  std::vector<bench::Size> sizes = {{160, 120}, {320, 256}, {640, 512}};
  const char* write_frames = nullptr;
  for (int i = 1; i < argc; ++i) {
    const bool has_value = i + 1 < argc;
    if (!std::strcmp(argv[i], "--help")) {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (!std::strcmp(argv[i], "--frames") && has_value) {
      if (!bench::parse_number_arg(argv[++i], frames, 10, std::numeric_limits<int>::max(), "bolo-vo-bench", "--frames", "at least 10")) return 2;
    } else if (!std::strcmp(argv[i], "--write-frames") && has_value) {
      write_frames = argv[++i];
    } else if (!std::strcmp(argv[i], "--mode") && has_value) {
      mode_name = argv[++i];
    } else if (!std::strcmp(argv[i], "--sizes") && has_value) {
      if (!bench::parse_size_list(argv[++i], sizes, "bolo-vo-bench")) return 2;
    } else if (!std::strcmp(argv[i], "--max-keyframes") && has_value) {
      if (!bench::parse_number_arg(argv[++i], max_keyframes, std::uint32_t{2}, vo::kMaxKeyframes, "bolo-vo-bench", "--max-keyframes", "2..8"))
        return 2;
    } else if (!std::strcmp(argv[i], "--carry-coring") && has_value) {
      if (!bench::parse_number_arg(argv[++i], carry_coring, 0.0f, 100.0f, "bolo-vo-bench", "--carry-coring", "0..100")) return 2;
    } else if (!std::strcmp(argv[i], "--smoothing") && has_value) {
      if (!bench::parse_number_arg(argv[++i], smoothing, std::uint32_t{0}, vo::kMaxSmoothingPasses, "bolo-vo-bench", "--smoothing", "0..3"))
        return 2;
    } else {
      std::fprintf(stderr, "bolo-vo-bench: unknown option or missing value: %s\n%s", argv[i], kUsage);
      return 2;
    }
  }
  vo::Photometric mode;
  if (!vo::parse_photometric(mode_name.c_str(), mode) || mode == vo::Photometric::ir_loop) {
    std::fprintf(stderr, "bolo-vo-bench: --mode wants none, affine or ir, got '%s'\n", mode_name.c_str());
    return 2;
  }
  // Sizes the VO refuses (the camera does not matter for that) are refused before any work.
  for (const bench::Size& size : sizes) {
    vo::VoConfig cfg;
    cfg.width = size.width, cfg.height = size.height, cfg.camera = {1, 1, 0, 0}, cfg.max_keyframes = max_keyframes;
    if (const char* why = vo::invalid_reason(cfg)) {
      std::fprintf(stderr, "bolo-vo-bench: %s: %s\n", size.label().c_str(), why);
      return 2;
    }
  }
  const double fps = bench::kVoBenchFps;
  if (write_frames != nullptr) {
    Frames f = render(sizes.front().width, sizes.front().height, frames, fps);
    bench::VoFrames out{sizes.front().width, sizes.front().height, f.camera, std::move(f.raw)};
    if (!bench::write_vo_frames(write_frames, out)) {
      std::fprintf(stderr, "bolo-vo-bench: cannot write %s\n", write_frames);
      return 1;
    }
    return 0;
  }
  std::printf("bolo-vo-bench: VO (%s, %u keyframes, carry coring %g, smoothing %u) on street/drive, %d frames at 60 Hz, tau 12 ms, one core (thread CPU time)\n",
              mode_name.c_str(), max_keyframes, static_cast<double>(carry_coring), smoothing, frames);
  std::printf("%-9s %9s %9s %10s %9s %12s %12s %12s\n", "size", "ms/frame", "fps", "x realtime", "ms/posed", "arena KiB", "peak RSS KiB", "heap allocs");
  for (const bench::Size& size : sizes) {
    const std::uint32_t w = size.width, h = size.height;
    const Frames f = render(w, h, frames, fps);
    vo::VoConfig cfg;
    cfg.width = w, cfg.height = h, cfg.camera = f.camera, cfg.photometric = mode, cfg.tau_init_s = 0.012f;
    cfg.max_keyframes = max_keyframes, cfg.carry_coring = carry_coring, cfg.smoothing = smoothing;
    std::vector<std::byte> arena(vo::Odometry::arena_bytes(cfg));
    std::memset(arena.data(), 0, arena.size());  // touch it: the peak below includes the arena
    vo::Odometry odometry(cfg, arena);
    if (!odometry.ok()) return 2;
    const Resident before_frames = resident_kib();
    long allocations = 0;
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = thread_cpu_s();
    int posed = 0, keyframes = 0;
    double posed_seconds = 0;
    for (int i = 0; i < frames; ++i) {
      vo::FrameInput in;
      in.raw = f.raw[static_cast<std::size_t>(i)];
      in.t_s = i / fps, in.exposure_s = 0.5 / fps, in.readout_prev_s = 0.5 / fps, in.chain_broken = i == 0;
      const double before = thread_cpu_s();
      vo::FrameResult r;
      count_allocations(allocations, [&] { r = odometry.process(in); });
      if (r.has_pose) posed_seconds += thread_cpu_s() - before, ++posed;
      keyframes += r.keyframe;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // Thread CPU time: the build machine is shared, wall time would count other processes' turns.
    const double seconds = thread_cpu_s() - cpu0;
    const Resident after_frames = resident_kib();
    char heap[32];
    if (allocations < 0)
      std::snprintf(heap, sizeof heap, "%s", "not counted");
    else
      std::snprintf(heap, sizeof heap, "%ld", allocations);
    std::printf("%-9s %9.2f %9.1f %10.2f %9.2f %12zu %12ld %12s   (%d of %d frames posed, %d keyframes; wall %.1f ms/frame;"
                " resident +%ld KiB file-backed, +%ld KiB anonymous)\n",
                size.label().c_str(), 1e3 * seconds / frames, frames / seconds, frames / seconds / fps,
                posed ? 1e3 * posed_seconds / posed : 0.0, arena.size() / 1024, after_frames.peak, heap, posed, frames,
                keyframes, 1e3 * wall / frames, after_frames.file - before_frames.file,
                after_frames.anonymous - before_frames.anonymous);
  }
  if (!BOLO_VO_BENCH_COUNTS_ALLOCATIONS)
    std::printf("heap allocations not counted: no counting allocator in this build, or a sanitizer owns malloc\n");
  std::printf("goal: >= 5x real time at 320x256, 60 Hz; no heap allocation while frames are processed (all VO memory is\n"
              "the arena). Resident memory grows during the first size only: code, stack and dynamic-linking pages\n"
              "touched the first time.\n");
  return 0;
}
