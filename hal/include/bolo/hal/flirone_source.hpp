#pragma once
// FLIR ONE (Gen 3, Pro) as a FrameSource: transfers from a BulkInTransport (libusb on a device, a
// captured log in tests) through the FlirOneReassembler, out as frames of raw 14-bit counts in
// the core's geometry (80x60, or 160x120: flirone::kGeometries) with the telemetry in the
// FrameHeader. Board-safe: no exceptions, buffers sized at construction.

#include <cstdint>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/hal/flirone_reassembler.hpp"
#include "bolo/hal/lepton_telemetry.hpp"
#include "bolo/hal/usb_transport.hpp"

namespace bolo::hal {

enum class FlirOneClock : std::uint8_t {
  camera,  // the JSON's usbNotifiedTimestamp (what the shared recording's t_s were made from)
  host,    // the transport's arrival time
};

struct FlirOneSourceConfig {
  std::uint32_t transfer_timeout_ms = 1000;
  std::uint32_t reconnect_timeout_ms = 2000;
  bool verify_crc = true;
  bool skip_duplicates = false;  // the core exports some frames twice; keep them by default
  FlirOneClock clock = FlirOneClock::camera;
  std::size_t max_frame_bytes = flirone::kDefaultMaxFrameBytes;
  std::size_t transfer_bytes = std::size_t{64} * 1024;
};

class FlirOneSource final : public FrameSource {
 public:
  FlirOneSource(BulkInTransport& transport, const FlirOneSourceConfig& config = {});
  // Reads up to the first good frame, or the first fault or end, and keeps what came for the
  // first stream_frame() (the caller sees the same statuses and counts as without it). After a
  // frame, format() has the camera's geometry; false otherwise.
  bool probe();
  // The stream's geometry: the first frame's (probe() or streamed). Asked before any frame, it is
  // 80x60 from then on. A frame of another geometry is counted corrupt and dropped.
  SourceFormat format() const override;
  // `fault` when a frame was lost (truncated, bad header/row/CRC, timeout, transfer error,
  // disconnect: each counted in stats()); after a disconnect it has already tried to reconnect
  // for reconnect_timeout_ms. end_of_stream only when a replayed log ends.
  StreamStatus stream_frame(fw::LineSink& sink) override;
  SourceStats stats() const override { return stats_; }
  // skipped_in_camera and counter_jumps (below), then the reassembler's counts that SourceStats
  // has no place for: stray_transfers, trailing_bytes, bad_status (a JSON status not read; the
  // frame is still delivered).
  ExtraCounters extra_counters() const override;
  // From the telemetry frame counter (LeptonFrameCounter): frames the core counted but the camera
  // never sent (those lost on the wire, counted short or corrupt, aside; each leaves a gap in
  // FrameHeader::sequence like a lost one), and steps too large to be losses (no gap). Repeats of
  // the previous frame's counter: stats().duplicates.
  std::uint64_t skipped_in_camera() const { return skipped_in_camera_; }
  std::uint64_t counter_jumps() const { return counter_.jumps(); }

  const FlirOneReassembler& reassembler() const { return reassembler_; }
  // The frame last delivered (telemetry, JSON status, JPEG).
  const FlirOneFrame& last_frame() const { return reassembler_.frame(); }

 private:
  StreamStatus next_whole_frame(std::int64_t& arrival_ns);
  StreamStatus deliver(fw::LineSink& sink, std::int64_t arrival_ns);
  bool lost_frames_since(const FlirOneCounters& before);
  void count_lost(std::uint64_t frames);
  void follow_frame_counter(std::uint32_t counter);

  BulkInTransport& transport_;
  FlirOneSourceConfig config_;
  FlirOneReassembler reassembler_;
  std::vector<std::uint8_t> transfer_;
  // Frames begun, good or lost, and frames the camera skipped: a missing frame leaves a gap.
  std::uint64_t sequence_ = 0;
  bool have_previous_ = false;
  bool connected_ = true;
  mutable const flirone::Geometry* geometry_ = nullptr;  // the first frame's, or format()'s answer
  bool held_ = false;  // probe() read something: held_status_ (a frame: still in the reassembler)
  StreamStatus held_status_ = StreamStatus::fault;
  std::int64_t held_arrival_ns_ = 0;
  std::uint32_t previous_counter_ = 0;
  LeptonFfcTracker ffc_;
  LeptonFrameCounter counter_;
  std::uint64_t lost_since_good_ = 0;  // frames lost on the wire since the last good frame
  std::uint64_t skipped_in_camera_ = 0;
  SourceStats stats_;
};

}  // namespace bolo::hal
