#pragma once
// FLIR ONE Pro frames from the bytes of bulk IN transfers (usb-thermal-cores.md, "FLIR ONE Pro").
// The protocol layer only: no I/O, no exceptions, one buffer allocated at construction
// (board-safe). The same code runs on libusb transfers and on a captured transfer log.
//
// Frame layout: a 28-byte header (7 x uint32 LE: magic 0xBEEF, 1, total length, thermal length,
// JPEG length, JSON length, timestamp), then the thermal part, the JPEG, the JSON status. The
// thermal length says the core's geometry (flirone::kGeometries): 10 332 bytes are 63 VoSPI
// packets (164 bytes: id with the row in its low 12 bits, CRC, 80 x uint16 LE), 80x60 and 3
// telemetry rows; 40 016 bytes are 122 rows of 328 bytes, each two halves of a 2-word prefix and
// 80 pixels (the layout the public drivers read), 160x120 and 2 telemetry rows.
//
// Rules: a transfer that begins with the magic starts a frame (an unfinished frame before it is
// counted as truncated); a transfer with no frame in progress that does not begin with the magic
// is stray. A frame is complete at 28 + total bytes; it is good when its lengths agree, its thermal
// length is a known geometry's and, in the VoSPI layout, every packet carries its own row id and
// (unless disabled) its CRC verifies (the 160x120 layout's prefixes are not checked: the drivers
// give them no meaning). Bytes after a frame's
// end in the same transfer start the next frame if they begin with the magic (collect it with
// poll()); otherwise they are counted as trailing and dropped.

#include <cstdint>
#include <span>
#include <vector>

#include "bolo/hal/flirone_status.hpp"
#include "bolo/hal/lepton_telemetry.hpp"

namespace bolo::hal {

namespace flirone {
inline constexpr std::uint32_t kMagic = 0xBEEF;
inline constexpr std::size_t kHeaderBytes = 28;
inline constexpr std::size_t kPacketBytes = 164;
inline constexpr std::size_t kPackets = 63;
inline constexpr std::size_t kThermalBytes = kPackets * kPacketBytes;  // 10332
inline constexpr std::uint32_t kWidth = 80;
inline constexpr std::uint32_t kHeight = 60;                 // image rows 0-59
inline constexpr std::uint32_t kTelemetryRows = 3;           // rows 60-62 (A, B, C)
inline constexpr std::size_t kDefaultMaxFrameBytes = std::size_t{512} * 1024;  // a frame is ~88 KB

// The thermal layouts, by payload size: the one table the parser, the source's format and the
// FrameHeader take their sizes from.
struct Geometry {
  std::size_t thermal_bytes;
  std::uint32_t width, height;  // image
  std::uint32_t telemetry_rows;  // rows after the image; row A's first 80 words are Lepton telemetry
  bool vospi_packets;            // 80-pixel VoSPI packets (id, CRC checked); else 160-pixel rows
};
inline constexpr Geometry kGeometries[] = {
    {kThermalBytes, kWidth, kHeight, kTelemetryRows, true},  // Gen 3 / Pro: Lepton 2.x class
    {std::size_t{122} * 328, 160, 120, 2, false},             // 160x120 core: 40 016 bytes
};
inline constexpr std::uint32_t kMaxWidth = 160, kMaxHeight = 120;
// The geometry of a thermal part of `thermal_bytes`; nullptr when no known layout has that size.
const Geometry* geometry_for(std::size_t thermal_bytes);
}  // namespace flirone

struct FlirOneFrame {
  std::uint32_t total_bytes = 0, jpeg_bytes = 0, json_bytes = 0;
  std::uint32_t header_timestamp = 0;  // the header's 7th word, as sent (not a clock we can use)
  const flirone::Geometry* geometry = &flirone::kGeometries[0];
  std::uint16_t pixels[flirone::kMaxHeight * flirone::kMaxWidth] = {};  // geometry->width per row
  std::uint16_t telemetry[flirone::kTelemetryRows][flirone::kMaxWidth] = {};
  LeptonTelemetry lepton;  // decoded row A
  FlirOneStatus status;
  bool status_ok = false;  // the JSON was present and readable
  std::span<const std::uint8_t> jpeg;  // into the reassembler's buffer; valid until next push/poll
};

struct FlirOneCounters {
  std::uint64_t frames = 0;          // good frames completed
  std::uint64_t truncated = 0;       // a new frame began before this one was complete
  std::uint64_t stray_transfers = 0; // data with no frame in progress
  std::uint64_t trailing_bytes = 0;  // bytes after a frame's end that did not start a frame
  std::uint64_t bad_header = 0;      // lengths inconsistent, over the buffer or of no known geometry
  std::uint64_t bad_row_id = 0;      // frames with a packet not carrying its row
  std::uint64_t bad_crc = 0;         // frames with a packet whose CRC does not verify
  std::uint64_t bad_status = 0;      // frames whose JSON could not be read (frame still good)
};

class FlirOneReassembler {
 public:
  explicit FlirOneReassembler(std::size_t max_frame_bytes = flirone::kDefaultMaxFrameBytes,
                              bool verify_crc = true);

  // One bulk transfer. True when a good frame completed with it: frame() holds it until the
  // next push_transfer()/poll().
  bool push_transfer(std::span<const std::uint8_t> transfer);
  // Completes a frame that is already whole in the buffer (bytes that followed a frame's end in
  // the same transfer). Call until false before the next transfer.
  bool poll();
  // Forgets any partial frame (after a device reset or reconnect); not counted.
  void reset() { have_ = consumed_ = 0; }

  const FlirOneFrame& frame() const { return frame_; }
  const FlirOneCounters& counters() const { return counters_; }
  std::size_t buffered() const { return have_ - consumed_; }

 private:
  void drop_delivered();
  bool complete_if_whole();
  bool decode(std::span<const std::uint8_t> bytes);

  std::vector<std::uint8_t> buffer_;
  std::size_t have_ = 0;
  std::size_t consumed_ = 0;  // bytes of the last delivered frame, dropped at the next call
  bool verify_crc_;
  FlirOneFrame frame_;
  FlirOneCounters counters_;
};

// Reads a little-endian uint32 (for header parsing here and in tests).
constexpr std::uint32_t read_le32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}

bool flirone_starts_frame(std::span<const std::uint8_t> bytes);

}  // namespace bolo::hal
