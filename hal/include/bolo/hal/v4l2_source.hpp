#pragma once
// A UVC Y16 camera through V4L2 (FLIR Lepton on PureThermal, FLIR Boson): format negotiation
// (Y16; for a 160-wide Lepton the 160x122 size with two telemetry rows when offered), mmap
// streaming over a ring of buffers, the driver's sequence numbers for dropped-frame detection,
// its timestamps, telemetry (FFC, FPA and housing temperature) where the format carries it.
// Host code: the constructor throws std::runtime_error naming the device; streaming never throws
// (faults are counted, an unplugged camera is reopened within reconnect_timeout_ms).

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/hal/lepton_telemetry.hpp"
#include "bolo/hal/y16_frame.hpp"

namespace bolo::hal {

enum class TelemetryRows : std::uint8_t { automatic, on, off };

struct V4l2Config {
  std::string path;              // /dev/videoN
  std::uint32_t width = 0;       // 0 = the largest Y16 size offered up to max_auto_pixels
  std::uint32_t height = 0;      // image rows (telemetry rows come on top)
  TelemetryRows telemetry = TelemetryRows::automatic;
  std::uint64_t max_auto_pixels = std::uint64_t{1280} * 1024;  // the automatic choice's limit
  std::uint32_t buffers = 4;
  std::uint32_t timeout_ms = 1000;
  std::uint32_t reconnect_timeout_ms = 2000;
};

struct V4l2Negotiated {
  std::string driver, card;
  std::uint32_t width = 0, image_rows = 0, telemetry_rows = 0, bytes_per_line = 0;
  std::uint32_t buffers = 0;
  std::uint32_t frame_period_ns = 0;
};

// A driver's frame sequence numbers -> the frames it numbered but never delivered. A number at
// or behind the highest seen arrives out of order: uvcvideo completes buffers from copy work that
// runs in parallel (an unbound workqueue), so two frames can swap under load. Such a frame was
// counted missing when the higher number came and is taken back (a repeated number is taken for
// such a frame too: the sequence alone cannot tell them apart).
class SequenceGaps {
 public:
  // False for a number at or behind the highest seen.
  bool add(std::uint32_t sequence);
  void restart() { have_ = false; }  // a reopened device numbers from 0 again
  std::uint64_t missing() const { return missing_; }
  std::uint64_t out_of_order() const { return late_; }

 private:
  bool have_ = false;
  std::uint32_t highest_ = 0;
  std::uint64_t missing_ = 0, late_ = 0;
};

// What V4l2Source makes of each buffer the driver hands over, apart from the device (tests feed
// it synthetic Y16 buffers): the driver's sequence numbers (drops, late frames), the layout
// check, the header (sequence kept increasing across a reopen, timestamp) and, from Lepton
// telemetry rows, FFC events, temperatures and the frame counter: frames skipped inside the
// camera (the driver never saw them, so its numbers show no gap; the delivered sequence gets one)
// and frames sent twice (SourceStats::duplicates, delivered all the same).
class V4l2BufferStream {
 public:
  struct Buffer {
    std::span<const std::uint8_t> bytes;  // what the driver filled (bytesused)
    std::uint32_t sequence = 0;           // the driver's frame number
    bool error = false;                   // V4L2_BUF_FLAG_ERROR
    bool timestamp_monotonic = false;     // V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC
    std::int64_t timestamp_ns = 0;
  };
  explicit V4l2BufferStream(const Y16Layout& layout);
  // Pushes the buffer's image rows into `sink` (`frame`) or counts in `stats` why not (`fault`).
  StreamStatus deliver(const Buffer& buffer, fw::LineSink& sink, SourceStats& stats);
  // The device was reopened (with `layout`): the driver numbers from 0 again.
  void reopened(const Y16Layout& layout);
  std::uint64_t out_of_order() const { return gaps_.out_of_order(); }
  // Frames the telemetry counter stepped over that the driver's numbers do not account for. Each
  // leaves a gap in the delivered FrameHeader::sequence (not in the driver's numbers, `dropped`).
  std::uint64_t skipped_in_camera() const { return skipped_in_camera_; }
  // Counter steps too large (or too far back) to be losses: a restarted core, a bad row.
  std::uint64_t counter_jumps() const { return counter_.jumps(); }
  const LeptonTelemetry& last_telemetry() const { return telemetry_; }

 private:
  void follow_sequence(std::uint32_t sequence, SourceStats& stats);
  fw::FrameHeader header_of(const Buffer& buffer) const;
  void telemetry_to_header(fw::FrameHeader& header);
  void follow_frame_counter(std::uint32_t sequence, SourceStats& stats);
  void push_image(const Y16Frame& frame, const fw::FrameHeader& header, fw::LineSink& sink);

  Y16Layout layout_;
  std::vector<std::uint16_t> line_;
  SequenceGaps gaps_;
  // Delivered sequence = the driver's number + this: it keeps sequences increasing across a reopen
  // and grows by the frames skipped in the camera, so that they leave a gap as the driver's drops do.
  std::uint64_t sequence_offset_ = 0;
  std::uint64_t last_sequence_ = 0;  // the delivered sequence of the last buffer
  bool have_ffc_stamp_ = false;
  std::uint32_t last_ffc_ms_ = 0;
  LeptonTelemetry telemetry_;
  LeptonFrameCounter counter_;
  bool have_counted_sequence_ = false;
  std::uint32_t counted_sequence_ = 0;  // the driver's highest number among frames with telemetry
  std::uint64_t skipped_in_camera_ = 0;
};

class V4l2Source final : public FrameSource {
 public:
  explicit V4l2Source(const V4l2Config& config);
  ~V4l2Source() override;
  SourceFormat format() const override;
  StreamStatus stream_frame(fw::LineSink& sink) override;
  SourceStats stats() const override { return stats_; }
  // out_of_order, skipped_in_camera and counter_jumps (below).
  ExtraCounters extra_counters() const override;
  const V4l2Negotiated& negotiated() const { return negotiated_; }
  const LeptonTelemetry& last_telemetry() const { return buffers_->last_telemetry(); }
  // Frames the driver handed over behind a higher sequence number (see SequenceGaps).
  std::uint64_t out_of_order() const { return buffers_->out_of_order(); }
  // From the Lepton telemetry frame counter (formats with telemetry rows): frames skipped inside
  // the camera, and counter jumps (see V4l2BufferStream). Repeats: stats().duplicates.
  std::uint64_t skipped_in_camera() const { return buffers_->skipped_in_camera(); }
  std::uint64_t counter_jumps() const { return buffers_->counter_jumps(); }

  struct Device;

 private:
  StreamStatus lost_device();
  Y16Layout layout() const;

  V4l2Config config_;
  std::unique_ptr<Device> device_;
  V4l2Negotiated negotiated_;
  std::optional<V4l2BufferStream> buffers_;  // from the first open on
  SourceStats stats_;
};

// The Y16 size V4L2Source asks for among the discrete sizes a driver offers (width, height as
// offered: a Lepton's 160x122 includes its two telemetry rows); nothing when none fits.
std::optional<std::pair<std::uint32_t, std::uint32_t>> choose_y16_size(
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& sizes, const V4l2Config& config);

struct V4l2DeviceEntry {
  std::string path, card, driver;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> y16_sizes;  // width, height
};
// /dev/video* capture nodes that offer Y16.
std::vector<V4l2DeviceEntry> list_v4l2_y16_devices();

}  // namespace bolo::hal
