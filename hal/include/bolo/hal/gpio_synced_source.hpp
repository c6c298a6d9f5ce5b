#pragma once
// Any FrameSource with the camera's GPIO lines beside it: each delivered frame is matched to the
// latest frame-sync edge at or before its timestamp (sync-to-frame latency), marked when the
// "FFC imminent" input was active (FrameHeader::ffc = imminent unless the frame shows an event),
// and a shutter triggered on request makes the next frame an FFC frame (FrameHeader::ffc =
// completed). Board-safe: no allocation after construction.

#include <cstdint>

#include "bolo/core/frame_source.hpp"
#include "bolo/hal/gpio_lines.hpp"

namespace bolo::hal {

struct GpioFrameMarks {
  bool sync_matched = false;
  std::int64_t sync_ns = 0;
  std::int64_t latency_ns = 0;  // frame timestamp - sync edge
  bool ffc_imminent = false;
  bool after_shutter = false;   // the frame follows a shutter pulse we sent
};

struct LatencyStats {
  std::uint64_t count = 0;
  std::int64_t min_ns = 0, max_ns = 0;
  std::int64_t sum_ns = 0;
  std::int64_t mean_ns() const { return count ? sum_ns / static_cast<std::int64_t>(count) : 0; }
};

class GpioSyncedSource final : public FrameSource {
 public:
  GpioSyncedSource(FrameSource& inner, GpioLines& gpio) : inner_(inner), gpio_(gpio) {}
  SourceFormat format() const override { return inner_.format(); }
  StreamStatus stream_frame(fw::LineSink& sink) override;
  SourceStats stats() const override { return inner_.stats(); }
  // The inner source's, then ffc_imminent_frames and sync_unmatched_frames.
  ExtraCounters extra_counters() const override;

  bool request_shutter();
  const GpioFrameMarks& last_marks() const { return marks_; }
  const LatencyStats& latency() const { return latency_; }
  std::uint64_t imminent_frames() const { return imminent_frames_; }
  std::uint64_t unmatched_frames() const { return unmatched_; }

 private:
  class Marker final : public fw::LineSink {
   public:
    Marker(GpioSyncedSource& owner, fw::LineSink& next) : owner_(owner), next_(next) {}
    void begin_frame(const fw::FrameHeader& header) override;
    void push_line(std::uint32_t row, fw::LineView line) override { next_.push_line(row, line); }
    void end_frame() override { next_.end_frame(); }

   private:
    GpioSyncedSource& owner_;
    fw::LineSink& next_;
  };

  void take_edges();
  void mark(fw::FrameHeader& header);

  static constexpr std::size_t kEdges = 64;  // recent sync edges kept (a few seconds at 30 Hz)
  FrameSource& inner_;
  GpioLines& gpio_;
  std::int64_t edges_[kEdges] = {};
  std::size_t edge_count_ = 0, edge_next_ = 0;
  bool shutter_pending_ = false;
  GpioFrameMarks marks_;
  LatencyStats latency_;
  std::uint64_t imminent_frames_ = 0, unmatched_ = 0;
};

}  // namespace bolo::hal
