#pragma once
// What a camera's GPIO lines must show over a stream through GpioSyncedSource (hil_gpio_camera,
// the real-device check): one frame-sync pulse per frame, each frame matched to its own pulse at
// most ~one frame period before its timestamp, and a requested shutter marking exactly the next
// frame. Pure: the frames' marks in, failures and figures out.

#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bolo/hal/gpio_synced_source.hpp"

namespace bolo::hil {

struct GpioCameraFrame {
  std::int64_t timestamp_ns = 0;
  bool timestamp_valid = false;
  hal::GpioFrameMarks marks;
};

struct GpioCameraPlan {
  bool sync = false;                            // a sync line was named
  std::optional<std::size_t> shutter_before;    // the shutter was requested before this frame
};

struct GpioCameraResult {
  std::vector<std::string> failures;
  std::int64_t median_interval_ns = 0, median_latency_ns = 0, max_latency_ns = 0;
  std::size_t shutter_marked = 0;   // frames marked as following our shutter pulse
  std::size_t imminent_frames = 0;  // frames during which "FFC imminent" was active
};

inline std::int64_t median_of(std::vector<std::int64_t> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

inline GpioCameraResult check_gpio_camera(std::span<const GpioCameraFrame> frames, const GpioCameraPlan& plan) {
  GpioCameraResult r;
  auto fail = [&](std::string what) { r.failures.push_back(std::move(what)); };
  std::vector<std::int64_t> intervals, latencies;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const GpioCameraFrame& f = frames[i];
    if (f.marks.ffc_imminent) ++r.imminent_frames;
    if (f.marks.after_shutter) ++r.shutter_marked;
    if (i > 0 && f.timestamp_valid && frames[i - 1].timestamp_valid)
      intervals.push_back(f.timestamp_ns - frames[i - 1].timestamp_ns);
    if (f.marks.sync_matched) latencies.push_back(f.marks.latency_ns);
  }
  r.median_interval_ns = median_of(intervals);
  r.median_latency_ns = median_of(latencies);
  r.max_latency_ns = latencies.empty() ? 0 : *std::max_element(latencies.begin(), latencies.end());
  if (frames.empty()) fail("no frames");
  if (plan.sync && !frames.empty()) {
    // The first frame may have been exposed before the line was opened; every later one needs a
    // pulse of its own.
    std::size_t unmatched = 0, shared = 0, late = 0, untimed = 0;
    for (std::size_t i = 1; i < frames.size(); ++i) {
      const GpioCameraFrame& f = frames[i];
      if (!f.timestamp_valid) {
        ++untimed;
        continue;
      }
      if (!f.marks.sync_matched) {
        ++unmatched;
        continue;
      }
      const GpioCameraFrame& prev = frames[i - 1];
      if (prev.marks.sync_matched && f.marks.sync_ns <= prev.marks.sync_ns) ++shared;
      if (f.marks.latency_ns < 0 || (r.median_interval_ns > 0 && 2 * f.marks.latency_ns > 3 * r.median_interval_ns))
        ++late;
    }
    if (untimed > 0) fail(std::to_string(untimed) + " frames without a time stamp to match a sync edge against");
    if (unmatched > 0) fail(std::to_string(unmatched) + " frames with no sync edge before them");
    if (shared > 0) fail(std::to_string(shared) + " frames matched to the previous frame's sync edge (a pulse missing)");
    if (late > 0) fail(std::to_string(late) + " frames more than 1.5 frame periods after their sync edge");
  }
  if (plan.shutter_before) {
    const std::size_t k = *plan.shutter_before;
    if (k >= frames.size()) fail("the stream ended before the frame after the shutter request");
    else if (!frames[k].marks.after_shutter) fail("frame " + std::to_string(k) + ", the one after the shutter pulse, is not marked as an FFC frame");
    if (r.shutter_marked != 1) fail(std::to_string(r.shutter_marked) + " frames marked as after the shutter pulse, want 1");
  } else if (r.shutter_marked != 0) {
    fail(std::to_string(r.shutter_marked) + " frames marked as after a shutter pulse nobody sent");
  }
  return r;
}

}  // namespace bolo::hil
