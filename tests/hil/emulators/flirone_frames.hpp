#pragma once
// FLIR ONE Pro frames as they travel over USB (docs: ../shared/docs/usb-thermal-cores.md):
// a 28-byte header, 63 VoSPI packets of thermal data, a JPEG and a JSON status string. Used by
// the emulator to send them and by the HIL test to know what must arrive.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace bolo::hil::flirone {

using Bytes = std::vector<std::uint8_t>;

inline constexpr std::size_t kHeaderBytes = 28;
inline constexpr std::size_t kPacketBytes = 164;
inline constexpr std::size_t kPackets = 63;
inline constexpr std::size_t kThermalBytes = kPacketBytes * kPackets;  // 10332
inline constexpr std::size_t kWidth = 80;
inline constexpr std::size_t kImageRows = 60;

struct Header {
  std::uint32_t magic = 0;
  std::uint32_t version = 0;
  std::uint32_t total = 0;  // thermal + jpeg + json, header excluded
  std::uint32_t thermal = 0;
  std::uint32_t jpeg = 0;
  std::uint32_t json = 0;
  std::uint32_t timestamp = 0;
};

bool starts_with_magic(std::span<const std::uint8_t> bytes);
Header read_header(std::span<const std::uint8_t> bytes);  // needs kHeaderBytes
void write_header(Bytes& frame, const Header& header);

// The Lepton frame counter in telemetry row A (packet 60, words 20-21).
std::uint32_t frame_counter(std::span<const std::uint8_t> frame);
void set_frame_counter(Bytes& frame, std::uint32_t counter);

// Row number of VoSPI packet `index` (low 12 bits of its id).
std::uint16_t packet_row(std::span<const std::uint8_t> frame, std::size_t index);
void set_packet_row(Bytes& frame, std::size_t index, std::uint16_t row);

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes);
// FNV-1a of the 60 image rows' pixels only (80 little-endian uint16 each, packet headers
// skipped): what a FrameSource delivers of the frame.
std::uint64_t image_hash(std::span<const std::uint8_t> frame);

// Sets every packet's CRC field: CRC-16-CCITT (0x1021, initial 0) over the packet read as
// big-endian 16-bit words, id's top 4 bits and the CRC field taken as zero. The FLIR ONE stores
// the words little-endian.
void seal_packets(Bytes& frame);

// The capture folder's transfers (hex text, 1.txt..N.txt in numeric order, empty ones kept as
// empty). Throws naming the file and offset of bad hex.
std::vector<Bytes> load_capture(const std::string& folder);

// Frames of a transfer sequence, found from the headers' lengths in the concatenated bytes
// (independent of any USB reassembly). Throws naming the byte offset of a broken header.
std::vector<Bytes> split_frames(const std::vector<Bytes>& transfers);

// Simulated frames in the capture's framing: `base` (a real frame) gives telemetry, JPEG and
// JSON; the image rows are a moving pattern of frame `index`, the counter is given. With
// `jpeg_bytes` smaller than the real JPEG, the JPEG part is cut to that length (transfer volume
// per frame is then mostly thermal, as when the host only asks for radiometric data).
class SimulatedFrames {
 public:
  SimulatedFrames(Bytes base, std::size_t jpeg_bytes);
  Bytes frame(std::uint64_t index, std::uint32_t counter) const;

 private:
  Bytes base_;
};

}  // namespace bolo::hil::flirone
