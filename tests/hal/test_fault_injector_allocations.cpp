// The fault injector allocates nothing after construction: malloc and operator new are replaced
// in this binary by counting versions, and 3000 frames with every kind of fault stream through
// the injector into the corrector.

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/firmware/pipeline.hpp"
#include "bolo/hal/fault_injector.hpp"
#include "fault_test_support.hpp"

#include "counting_allocator.hpp"  // replaces malloc/new in this binary

using bolo::test::g_allocations;
using bolo::test::g_counting;

int main() {
  if (!BOLO_COUNTING_ALLOCATOR_ACTIVE) {
    std::printf("SKIPPED: a sanitizer owns malloc in this build; heap allocations cannot be counted\n");
    return bolo::test::kSkipExitCode;
  }
  using namespace bolo;
  g_counting = true;
  int* probe = new int(1);  // the counter must see allocations, or a zero would prove nothing
  bolo::test::g_escape = probe;
  delete probe;
  g_counting = false;
  if (g_allocations.load() != 1) {
    std::printf("FAILED: the counting allocator does not see operator new\n");
    return 1;
  }
  g_allocations = 0;

  constexpr std::uint32_t W = 64, H = 48;
  test::SyntheticCamera camera(W, H, 3000, 101);
  hal::FaultInjectorConfig cfg;
  cfg.seed = 7;
  cfg.rates = {20'000, 20'000, 20'000, 20'000, 30'000, 15'000, 15'000, 15'000};
  hal::FaultInjector injector(camera, cfg);
  fw::PipelineConfig pc;
  pc.corrector.width = W;
  pc.corrector.height = H;
  pc.corrector.tau = {12'000'000, 12'000'000};
  pc.use_bad_pixels = true;
  std::vector<fw::Pixel> arena(fw::Pipeline::arena_pixels(pc));
  test::HashingCollector sink(W, H);
  fw::Pipeline pipeline(pc, arena, sink);

  g_counting = true;
  std::uint64_t frames = 0;
  while (injector.stream_frame(pipeline.input()) == hal::StreamStatus::frame) ++frames;
  g_counting = false;

  const hal::FaultCounts& c = injector.faults();
  std::printf("%llu frames delivered (%llu dropped, %llu duplicated, %llu reordered, %llu truncated, "
              "%llu corrupted, %llu mis-sized, %llu repeated lines, %llu ffc flips); %ld allocations\n",
              static_cast<unsigned long long>(frames), static_cast<unsigned long long>(c.dropped),
              static_cast<unsigned long long>(c.duplicated), static_cast<unsigned long long>(c.reordered),
              static_cast<unsigned long long>(c.truncated), static_cast<unsigned long long>(c.corrupted),
              static_cast<unsigned long long>(c.missized_lines),
              static_cast<unsigned long long>(c.repeated_lines),
              static_cast<unsigned long long>(c.ffc_flipped_on + c.ffc_flipped_off),
              g_allocations.load());
  const bool ok = g_allocations.load() == 0 && frames > 2900 && c.dropped > 0 && c.truncated > 0;
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
