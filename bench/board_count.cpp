// bolo-board-count: a fixed amount of firmware work and nothing else, built for the boards too,
// so that scripts/board-cost.sh can count the instructions it executes under qemu-user. Two runs
// with different frame counts differ by exactly those frames' work; no timing, no calibration.
//
//   bolo-board-count pipeline|corrector WxH FRAMES   bolo-bench's workloads (after their warm-up)
//   bolo-board-count vo FILE FRAMES                  the VO (bolo-vo-bench's settings) over the
//                                                    first FRAMES frames of FILE, written on the
//                                                    host by bolo-vo-bench --write-frames

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "number_arg.hpp"
#include "scene.hpp"
#include "size_list.hpp"
#include "workloads.hpp"
#if BOLO_BOARD_COUNT_VO
#include "bolo/vo/odometry.hpp"
#include "vo_frames_file.hpp"
#endif

namespace {

using namespace bolo;

constexpr const char* kUsage =
    "usage: bolo-board-count pipeline|corrector WxH FRAMES\n"
    "       bolo-board-count vo FILE FRAMES\n";

int run_stage(const std::string& stage, const char* size_text, const char* frames_text) {
  std::vector<bench::Size> sizes;
  std::size_t frames = 0;
  if (!bench::parse_size_list(size_text, sizes, "bolo-board-count") || sizes.size() != 1 ||
      !bench::parse_number_arg(frames_text, frames, std::size_t{0}, std::size_t{1} << 20,
                               "bolo-board-count", "FRAMES", "0..1048576"))
    return 2;
  const bench::BenchData data = bench::make_bench_data(sizes[0].width, sizes[0].height, 4);
  std::uint64_t checksum = 0, not_applied = 0;
  if (stage == "pipeline") {
    bench::PipelineWorkload w(data);
    w.run(frames);
    checksum = w.checksum(), not_applied = w.not_applied();
  } else {
    bench::CorrectorWorkload w(data);
    w.run(frames);
    checksum = w.checksum(), not_applied = w.not_applied();
  }
  std::printf("%s %s: %zu frames, checksum %llu\n", stage.c_str(), size_text, frames,
              static_cast<unsigned long long>(checksum));
  return not_applied == 0 ? 0 : 1;
}

#if BOLO_BOARD_COUNT_VO
int run_vo(const char* path, const char* frames_text) {
  bench::VoFrames f;
  int frames = 0;
  if (!bench::parse_number_arg(frames_text, frames, 0, 1 << 20, "bolo-board-count", "FRAMES",
                               "0..1048576"))
    return 2;
  if (!bench::read_vo_frames(path, f) || static_cast<std::size_t>(frames) > f.frames.size()) {
    std::fprintf(stderr, "bolo-board-count: %s: unreadable or fewer than %d frames\n", path, frames);
    return 2;
  }
  vo::VoConfig cfg = bench::vo_bench_config(f);
  std::vector<std::byte> arena(vo::Odometry::arena_bytes(cfg));
  vo::Odometry odometry(cfg, arena);
  if (!odometry.ok()) return 2;
  int posed = 0;
  for (int i = 0; i < frames; ++i) posed += odometry.process(bench::vo_frame_input(f, i)).has_pose;
  std::printf("vo %ux%u: %d frames, %d posed\n", f.width, f.height, frames, posed);
  return 0;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && (!std::strcmp(argv[1], "pipeline") || !std::strcmp(argv[1], "corrector")))
    return run_stage(argv[1], argv[2], argv[3]);
#if BOLO_BOARD_COUNT_VO
  if (argc == 4 && !std::strcmp(argv[1], "vo")) return run_vo(argv[2], argv[3]);
#endif
  std::fputs(kUsage, stderr);
  return 2;
}
