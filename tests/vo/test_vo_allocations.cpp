// Proves the VO core allocates nothing after initialisation: malloc and operator new
// are replaced in this binary by counting versions, and rendered street/drive frames (rendered
// before counting starts) go through the VO in every mode: initialisation, tracking, depth
// search, keyframes, window BA, tau refinement, a shutter event, a restart after losing track.

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#include "bolo/vo/odometry.hpp"
#include "rendered_pair.hpp"


#include "counting_allocator.hpp"  // replaces malloc/new in this binary

using bolo::test::g_allocations;
using bolo::test::g_counting;

namespace {
int failures = 0;
void check(bool ok, const char* what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAILED", what);
  if (!ok) ++failures;
}

}  // namespace

using namespace bolo;

int main() {
  if (!BOLO_COUNTING_ALLOCATOR_ACTIVE) {
    std::printf("SKIPPED: a sanitizer owns malloc in this build; heap allocations cannot be counted\n");
    return bolo::test::kSkipExitCode;
  }
  g_counting = true;
  {
    auto* probe = new std::vector<int>(100);
    delete probe;
  }
  g_counting = false;
  check(g_allocations.load() > 0, "the counter sees allocations");

  bolo::test::RenderedSequence seq{"street", "drive", 160, 120};
  std::vector<std::vector<std::uint16_t>> frames;
  for (int i = 0; i < 60; ++i) frames.push_back(seq.frame(2.0 + i / 60.0));
  // Then the same frames backwards: a jump the tracker loses, and a restart.
  for (int i = 59; i >= 0; i -= 6) frames.push_back(frames[static_cast<std::size_t>(i)]);
  std::vector<std::uint16_t> corrected(frames[0].size());

  struct Run {
    vo::Photometric mode;
    bool marginalisation_prior;  // with a window of 3, so that keyframes retire into it
  };
  for (const Run run : {Run{vo::Photometric::none, false}, Run{vo::Photometric::affine, false},
                        Run{vo::Photometric::ir, false}, Run{vo::Photometric::ir_loop, false},
                        Run{vo::Photometric::affine, true}}) {
    const vo::Photometric mode = run.mode;
    vo::VoConfig cfg;
    cfg.width = 160, cfg.height = 120, cfg.camera = seq.intrinsics(), cfg.photometric = mode;
    if (run.marginalisation_prior) cfg.marginalisation_prior = true, cfg.max_keyframes = 3;
    std::vector<std::byte> arena(vo::Odometry::arena_bytes(cfg));
    vo::Odometry odometry(cfg, arena);
    check(odometry.ok(), "set up");
    std::uint32_t posed = 0, keyframes = 0;
    g_allocations = 0;
    g_counting = true;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      vo::FrameInput in;
      in.raw = frames[i];
      if (mode == vo::Photometric::ir_loop) in.corrected = frames[i];
      in.t_s = static_cast<double>(i) / 60.0, in.exposure_s = 1.0 / 120, in.readout_prev_s = 1.0 / 120;
      in.chain_broken = i == 0 || i == 30;  // a shutter event mid-way
      const vo::FrameResult r = odometry.process(in);
      posed += r.has_pose, keyframes += r.keyframe;
    }
    g_counting = false;
    std::printf("%s%s: %u of %zu frames posed, %u keyframes, %ld allocations\n", vo::to_string(mode),
                run.marginalisation_prior ? " (marginalisation prior)" : "", posed, frames.size(), keyframes,
                g_allocations.load());
    check(posed > 10 && keyframes > 1, "the VO tracked and made keyframes (the paths ran)");
    if (run.marginalisation_prior) check(keyframes > cfg.max_keyframes, "keyframes retired into the prior");
    check(g_allocations.load() == 0, "no heap allocation while processing frames");
  }
  return failures == 0 ? 0 : 1;
}
