#pragma once
// The real-camera checks' stream loop (hil_*_hal --real): frames until `frames` have arrived or
// none has for 15 s, with the source's counters as they stood at the first frame (timeouts
// before it are the camera's start-up, not faults).

#include <chrono>
#include <cstdint>
#include <optional>

#include "bolo/core/frame_source.hpp"

namespace bolo::hil {

struct RealStreamRun {
  double seconds = 0;
  std::optional<hal::SourceStats> at_first_frame;
  // Timeouts before the first frame (all of them when none arrived).
  std::uint64_t startup_timeouts(const hal::SourceStats& now) const {
    return at_first_frame ? at_first_frame->timeouts : now.timeouts;
  }
};

// `delivered()` counts the frames the sink has taken whole; `on_frame()` runs after each new one.
template <class Delivered, class OnFrame>
RealStreamRun stream_real(hal::FrameSource& source, fw::LineSink& sink, std::uint64_t frames, Delivered delivered,
                          OnFrame on_frame) {
  using Clock = std::chrono::steady_clock;
  RealStreamRun run;
  const auto start = Clock::now();
  auto last_progress = start;
  while (delivered() < frames) {
    const std::uint64_t before = delivered();
    source.stream_frame(sink);
    if (delivered() != before) {
      last_progress = Clock::now();
      if (!run.at_first_frame) run.at_first_frame = source.stats();
      on_frame();
    } else if (Clock::now() - last_progress > std::chrono::seconds(15)) {
      break;
    }
  }
  run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return run;
}

template <class Delivered>
RealStreamRun stream_real(hal::FrameSource& source, fw::LineSink& sink, std::uint64_t frames, Delivered delivered) {
  return stream_real(source, sink, frames, delivered, [] {});
}

}  // namespace bolo::hil
