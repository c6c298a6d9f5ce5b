#include "bolo/hal/gpio_synced_source.hpp"

namespace bolo::hal {

bool GpioSyncedSource::request_shutter() {
  const bool ok = gpio_.pulse_shutter();
  shutter_pending_ = shutter_pending_ || ok;
  return ok;
}

ExtraCounters GpioSyncedSource::extra_counters() const {
  ExtraCounters c = inner_.extra_counters();
  c.add("ffc_imminent_frames", imminent_frames_);
  c.add("sync_unmatched_frames", unmatched_);
  return c;
}

void GpioSyncedSource::take_edges() {
  std::int64_t batch[16];
  for (;;) {
    const std::size_t n = gpio_.drain_sync_edges(batch);
    for (std::size_t i = 0; i < n; ++i) {
      edges_[edge_next_] = batch[i];
      edge_next_ = (edge_next_ + 1) % kEdges;
      if (edge_count_ < kEdges) ++edge_count_;
    }
    if (n < sizeof batch / sizeof batch[0]) return;
  }
}

void GpioSyncedSource::mark(fw::FrameHeader& header) {
  take_edges();
  marks_ = GpioFrameMarks{};
  marks_.ffc_imminent = gpio_.ffc_imminent();
  if (marks_.ffc_imminent) ++imminent_frames_;
  if (shutter_pending_) {
    marks_.after_shutter = true;
    header.ffc = fw::FfcState::completed;
    shutter_pending_ = false;
  } else if (marks_.ffc_imminent && !fw::shutter_event(header.ffc)) {
    header.ffc = fw::FfcState::imminent;  // the line announces an event; the source saw none here
  }
  if (header.timestamp_valid) {
    for (std::size_t i = 0; i < edge_count_; ++i) {
      const std::int64_t edge = edges_[(edge_next_ + kEdges - 1 - i) % kEdges];
      if (edge <= header.timestamp_ns && (!marks_.sync_matched || edge > marks_.sync_ns)) {
        marks_.sync_matched = true;
        marks_.sync_ns = edge;
      }
    }
  }
  if (!marks_.sync_matched) {
    ++unmatched_;
    return;
  }
  marks_.latency_ns = header.timestamp_ns - marks_.sync_ns;
  if (latency_.count == 0 || marks_.latency_ns < latency_.min_ns) latency_.min_ns = marks_.latency_ns;
  if (latency_.count == 0 || marks_.latency_ns > latency_.max_ns) latency_.max_ns = marks_.latency_ns;
  latency_.sum_ns += marks_.latency_ns;
  ++latency_.count;
}

void GpioSyncedSource::Marker::begin_frame(const fw::FrameHeader& header) {
  fw::FrameHeader marked = header;
  owner_.mark(marked);
  next_.begin_frame(marked);
}

StreamStatus GpioSyncedSource::stream_frame(fw::LineSink& sink) {
  Marker marker(*this, sink);
  const StreamStatus s = inner_.stream_frame(marker);
  if (s != StreamStatus::frame) take_edges();  // keep the ring current while frames fail
  return s;
}

}  // namespace bolo::hal
