#pragma once
// Seek Thermal Compact / CompactPro as a FrameSource, driven as the public driver
// (libseek-thermal) drives it: its start-up sequence (seek_startup.hpp), the start-up frame
// first (dead pixels), one frame request per frame, the latest shutter frame kept and
// subtracted from each image, dead pixels filled, the active area delivered (seek_image.hpp).
// Calibration frames are consumed; a shutter frame marks the next image as after an FFC. Runs
// over a VendorUsbTransport: libusb on a device, a scripted device in tests. Board-safe.

#include <cstdint>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/hal/seek_frame_parser.hpp"
#include "bolo/hal/seek_image.hpp"
#include "bolo/hal/seek_startup.hpp"
#include "bolo/hal/usb_transport.hpp"

namespace bolo::hal {


struct SeekSourceConfig {
  std::uint32_t transfer_timeout_ms = 1000;
  // A requested frame is waited for over this many timeouts in a row before it is given up and
  // asked for again (1: at the first). The camera sends only what was asked for, so what comes
  // after a pause can only be the rest of that frame; one that abandoned it stays silent.
  std::uint32_t timeouts_before_giving_up = 2;
  std::uint32_t reconnect_timeout_ms = 2000;
  // Frames without an image (boot and calibration frames) before a call gives up with a fault.
  std::uint32_t max_frames_without_image = 64;
  // Deliver 0x4000 + image - shutter (the driver's output). Off: the raw active area (dead
  // pixels still filled), delivered from the first image on.
  bool subtract_shutter = true;
};

struct SeekCounters {
  std::uint64_t shutter_frames = 0;      // FFC events seen
  std::uint64_t calibration_frames = 0;  // other non-image frames consumed
  std::uint64_t startup_frames = 0;
  std::uint64_t start_failures = 0;      // opens that failed (a step refused, no start-up frame)
  std::uint64_t images_before_shutter = 0;  // consumed: nothing to subtract yet
  // The frame counter moved by other than +1 (a duplicate aside): frames lost on the way (a gap of
  // up to kSeekPlausibleGap also adds to SourceStats::dropped) or a counter surprise.
  std::uint64_t counter_jumps = 0;
};

// Counter gaps up to this many frames are counted as dropped frames (8 s of a Compact's stream);
// a larger jump is a counter surprise, not that many losses.
inline constexpr std::uint16_t kSeekPlausibleGap = 64;

class SeekSource final : public FrameSource {
 public:
  SeekSource(VendorUsbTransport& transport, const SeekModel& model, const SeekSourceConfig& config = {});
  ~SeekSource() override;  // the close sequence: the camera left in operation mode 0
  SourceFormat format() const override;
  StreamStatus stream_frame(fw::LineSink& sink) override;
  SourceStats stats() const override { return stats_; }
  // counters() by name.
  ExtraCounters extra_counters() const override;

  // Closes the shutter for a calibration (an FFC event the stream then reports).
  bool request_shutter();
  const SeekCounters& counters() const { return counters_; }
  // From the last start-up frame: one byte per active pixel (1 = dead), row by row.
  std::span<const std::uint8_t> dead_map() const { return corrector_.dead_map(); }
  std::uint32_t dead_pixels() const { return corrector_.dead_pixels(); }
  std::span<const std::uint8_t> firmware_info() const { return {firmware_, sizeof firmware_}; }
  std::span<const std::uint8_t> chip_id() const { return {chip_id_, sizeof chip_id_}; }

 private:
  enum class Read : std::uint8_t { frame, waiting, lost, gone };
  TransferStatus start();
  TransferStatus send_startup_sequence();
  TransferStatus send(const SeekControlStep& step);
  void close_camera();
  bool drain();
  Transfer request_frame();
  Read read_frame(std::int64_t& arrival_ns);
  Read read_chunks(std::int64_t& arrival_ns);
  Read on_timeout();
  bool starts_a_frame(const SeekFrameInfo& info) const;
  StreamStatus resynchronise();
  StreamStatus device_gone();
  bool follow_counter(const SeekFrameInfo& info);

  VendorUsbTransport& transport_;
  SeekSourceConfig config_;
  SeekFrameParser parser_;
  SeekStartupSequence startup_;
  SeekImageCorrector corrector_;
  std::vector<std::uint8_t> chunk_;
  bool started_ = false;
  bool connected_ = true;
  bool ffc_pending_ = false;
  bool frame_requested_ = false;      // asked for and not yet whole, given up or failed
  std::uint32_t silent_timeouts_ = 0;  // timeouts in a row while it is awaited
  bool check_alignment_ = false;      // a frame was lost: the next must begin like one (resynchronise)
  std::uint64_t sequence_ = 0;
  bool have_counter_ = false;  // since the (re)start
  std::uint16_t previous_counter_ = 0;
  std::uint8_t firmware_[4] = {};
  std::uint8_t chip_id_[12] = {};
  std::uint8_t reply_[64] = {};  // the other reads of the start-up sequence
  SeekCounters counters_;
  SourceStats stats_;
};

}  // namespace bolo::hal
