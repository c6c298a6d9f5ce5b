#pragma once
// Seek Thermal Compact / CompactPro frames (usb-thermal-cores.md, "Seek Thermal"): assembling a
// requested frame from bulk chunks, its type and counter. The protocol layer only: no I/O, no
// exceptions, buffers allocated at construction (board-safe).
//
// A frame is width x height uint16 LE words. The type is word 10 (Compact) or word 2 (Pro); the
// counter word 40 (Compact) or word 1 (Pro), both in row 0. Type 3 is an image, 1 a
// shutter-closed calibration frame (an FFC event), 4 the first frame after start-up. The image
// is the active area (`crop`, the public driver's rectangle); the metadata rows lie outside it.

#include <cstdint>
#include <span>
#include <vector>

namespace bolo::hal {

enum class SeekFamily : std::uint8_t { compact, compact_pro };  // which start-up sequence

// The active image area inside the raw frame.
struct SeekCrop {
  std::uint32_t x, y, width, height;
  std::uint32_t pixels() const { return width * height; }
};

struct SeekModel {
  const char* name;
  SeekFamily family;
  std::uint16_t product_id;
  std::uint32_t width, height;  // the whole frame as transferred
  SeekCrop crop;                // what is delivered
  std::uint32_t type_word, counter_word;
  std::uint32_t chunk_bytes;    // bulk read size
  std::uint32_t max_fps;
  std::uint32_t pixels() const { return width * height; }
  std::uint32_t frame_bytes() const { return pixels() * 2; }
};

inline constexpr std::uint16_t kSeekVendorId = 0x289d;
// Compact: columns 0..206, rows 1..154; CompactPro: columns 1..320, rows 4..243.
inline constexpr SeekModel kSeekCompact{"compact", SeekFamily::compact, 0x0010, 208, 156, {0, 1, 207, 154},
                                        10, 40, 16224, 8};
inline constexpr SeekModel kSeekCompactPro{"compactpro", SeekFamily::compact_pro, 0x0011, 342, 260,
                                           {1, 4, 320, 240}, 2, 1, 13680, 15};

enum class SeekFrameKind : std::uint8_t {
  image,                // 3
  shutter,              // 1: shutter closed, an FFC event
  startup,              // 4: first frame, gives the dead-pixel map
  before_calibration,   // 6
  after_calibration,    // 20
  startup_calibration,  // 8, 7
  other,                // the other boot frames (9, 14, 25-28) and anything unknown
};

SeekFrameKind seek_frame_kind(std::uint16_t type);
// One of the types the facts doc lists (1, 3, 4, 6, 7, 8, 20 and the boot types 9, 14, 25-28).
// A chunk from the middle of a frame has pixel data where the type word is, which a sensor's
// counts practically never make one of these small numbers.
bool seek_frame_type_known(std::uint16_t type);

enum class SeekChunk : std::uint8_t {
  need_more,  // keep reading
  complete,   // the whole frame has arrived
  aborted,    // a zero-length read: the frame is given up (never wait on it)
  overflow,   // more bytes than the frame has: the frame is given up
};

struct SeekFrameInfo {
  SeekFrameKind kind = SeekFrameKind::other;
  std::uint16_t type = 0;
  std::uint16_t counter = 0;
};

class SeekFrameParser {
 public:
  explicit SeekFrameParser(const SeekModel& model);
  const SeekModel& model() const { return model_; }

  // Frame assembly: begin() before the first chunk of a requested frame.
  void begin() { have_ = 0; }
  SeekChunk add_chunk(std::span<const std::uint8_t> chunk);
  std::size_t received() const { return have_; }

  // Decodes the complete frame (add_chunk returned `complete`), or a frame given whole.
  // False when `frame` is not exactly one frame.
  bool parse(std::span<const std::uint8_t> frame, SeekFrameInfo& info);
  bool parse_received(SeekFrameInfo& info) { return parse({bytes_.data(), have_}, info); }

  // The last parsed frame, all width x height words (metadata included), host-endian.
  std::span<const std::uint16_t> words() const { return words_; }

 private:
  SeekModel model_;
  std::vector<std::uint8_t> bytes_;
  std::size_t have_ = 0;
  std::vector<std::uint16_t> words_;
};

}  // namespace bolo::hal
