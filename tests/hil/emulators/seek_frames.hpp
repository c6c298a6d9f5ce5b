#pragma once
// Seek Thermal Compact / CompactPro frames as the camera sends them
// (../shared/docs/usb-thermal-cores.md): uint16 LE words, frame type and counter in row 0
// (`Layout`); the boot sequence of frame types, shutter cycles (6, 1, 20) after the boot and
// every `shutter_period` images.
//
// Like the camera's raw output, every frame but the start-up frame carries a per-pixel offset
// pattern that changes at each shutter event: an image is scene + pattern, a shutter (and any
// calibration) frame a flat level + pattern, so only an image minus the latest shutter frame
// shows the scene. The start-up frame is flat with 5 dead pixels stuck low, which the public
// driver's histogram rule finds. `expected_image` is what a host that drives the camera as the
// public driver does must deliver, computed here on its own (not with the HAL's code).

#include <cstdint>
#include <vector>

namespace bolo::hil::seek {

using Bytes = std::vector<std::uint8_t>;

inline constexpr std::uint16_t kVendor = 0x289d;
inline constexpr std::uint16_t kImage = 3;
inline constexpr std::uint16_t kShutter = 1;
inline constexpr std::uint16_t kStartup = 4;

// Where the start-up frame has dead pixels (x, y, value), all inside the active area and apart.
struct DeadPixel {
  std::uint32_t x, y;
  std::uint16_t value;
};

// A camera model's frame as sent, and the active area a host delivers.
struct Layout {
  const char* name;
  std::uint16_t product_id;
  std::uint32_t width, height;
  std::uint32_t type_word, counter_word;
  std::uint32_t chunk_bytes;
  std::uint32_t active_x, active_y, active_width, active_height;
  DeadPixel dead[5];
  std::uint32_t pixels() const { return width * height; }
  std::uint32_t frame_bytes() const { return pixels() * 2; }
};

// Compact: 208x156, type word 10, counter word 40, active columns 0..206, rows 1..154.
inline constexpr Layout kCompact{"compact", 0x0010, 208, 156, 10, 40, 16224, 0, 1, 207, 154,
                                 {{17, 9, 0x0000}, {100, 77, 300}, {5, 150, 0x0000}, {200, 3, 1000}, {150, 120, 0x0000}}};
// CompactPro: 342x260, type word 2, counter word 1, active columns 1..320, rows 4..243.
inline constexpr Layout kCompactPro{"compactpro", 0x0011, 342, 260, 2, 1, 13680, 1, 4, 320, 240,
                                    {{17, 9, 0x0000}, {100, 77, 300}, {5, 150, 0x0000}, {300, 200, 1000}, {150, 243, 0x0000}}};

// The frame-type sequence: boot frames, a shutter cycle, then images with a shutter cycle every
// `shutter_period` images.
class FrameTypes {
 public:
  explicit FrameTypes(std::uint32_t shutter_period) : period_(shutter_period) {}
  std::uint16_t next();

 private:
  std::uint32_t period_;
  std::uint64_t emitted_ = 0;
  std::uint32_t images_since_shutter_ = 0;
  int shutter_step_ = 0;  // -1: not in a shutter cycle; the boot ends in one
};

// A frame of type `type` with counter `counter`; image content from `index`, the offset pattern
// of shutter event `epoch`.
Bytes make_frame(const Layout& l, std::uint64_t index, std::uint16_t type, std::uint16_t counter,
                 std::uint32_t epoch);

// The active area of clamp(0x4000 + image - shutter), each dead pixel of the start-up frame the
// mean of its 4-neighbours inside the area (they are live: the dead pixels lie apart).
std::vector<std::uint16_t> expected_image(const Layout& l, const Bytes& image, const Bytes& shutter);

}  // namespace bolo::hil::seek
