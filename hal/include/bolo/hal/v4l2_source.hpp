#pragma once
// A UVC camera through V4L2 (FLIR Lepton on PureThermal, FLIR Boson): format negotiation (Y16,
// the raw counts, first; else the 8-bit tone-mapped GREY, YUYV, UYVY, marked as such; a Lepton's
// telemetry sizes 160x122 and 80x63 when offered), mmap
// streaming over a ring of buffers, the driver's sequence numbers for dropped-frame detection,
// its timestamps, telemetry (FFC, FPA and housing temperature) where the format carries it.
// Host code: the constructor throws std::runtime_error naming the device; streaming never throws
// (faults are counted, an unplugged camera is reopened within reconnect_timeout_ms).

#include <cstdint>
#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/hal/lepton_telemetry.hpp"
#include "bolo/hal/y16_frame.hpp"

namespace bolo::hal {

enum class TelemetryRows : std::uint8_t { automatic, on, off };

// The formats taken, in the order tried when none is forced: Y16 (the core's 16-bit counts), then the
// 8-bit modes: GREY (the camera's tone-mapped grey), YUYV and UYVY (their luma; after a colour
// palette that need not rise with the scene's temperature).
inline constexpr std::array<V4l2Pixels, 4> kV4l2PixelOrder{V4l2Pixels::y16, V4l2Pixels::grey, V4l2Pixels::yuyv,
                                                           V4l2Pixels::uyvy};
// "Y16", "GREY", "YUYV", "UYVY" (V4L2's fourcc names).
const char* v4l2_pixels_name(V4l2Pixels pixels);
// The format a name gives (case-insensitive), nothing for another name.
std::optional<V4l2Pixels> v4l2_pixels_named(std::string_view name);
std::uint32_t v4l2_pixels_fourcc(V4l2Pixels pixels);

struct V4l2Config {
  std::string path;              // /dev/videoN
  std::optional<V4l2Pixels> pixels;  // a forced format; none = the first offered in kV4l2PixelOrder
  std::uint32_t width = 0;       // 0 = the largest size offered up to max_auto_pixels
  std::uint32_t height = 0;      // image rows (telemetry rows come on top)
  TelemetryRows telemetry = TelemetryRows::automatic;
  std::uint64_t max_auto_pixels = std::uint64_t{1280} * 1024;  // the automatic choice's limit
  std::uint32_t buffers = 4;
  std::uint32_t timeout_ms = 1000;
  std::uint32_t reconnect_timeout_ms = 2000;
};

struct V4l2Negotiated {
  std::string driver, card;
  V4l2Pixels pixels = V4l2Pixels::y16;
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
  LeptonFfcTracker ffc_;
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

using V4l2Sizes = std::vector<std::pair<std::uint32_t, std::uint32_t>>;  // width, height

// The size V4L2Source asks for among the discrete sizes a driver offers in a format (width,
// height as offered: a Lepton's 160x122 and 80x63 include its telemetry rows, Y16 only); nothing
// when none fits.
std::optional<std::pair<std::uint32_t, std::uint32_t>> choose_frame_size(const V4l2Sizes& sizes,
                                                                        const V4l2Config& config,
                                                                        V4l2Pixels pixels = V4l2Pixels::y16);

struct V4l2DeviceEntry {
  struct Format {
    V4l2Pixels pixels;
    V4l2Sizes sizes;
  };
  std::string path, card, driver;
  std::vector<Format> formats;  // those of kV4l2PixelOrder the node offers, in that order
  // The sizes offered in `pixels`; empty when the node does not offer it.
  V4l2Sizes sizes(V4l2Pixels pixels) const;
};
// /dev/video* capture nodes that offer Y16, GREY, YUYV or UYVY.
std::vector<V4l2DeviceEntry> list_v4l2_devices();

}  // namespace bolo::hal
