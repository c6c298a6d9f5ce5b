#pragma once
// Seek Thermal Compact frames as the camera sends them (../shared/docs/usb-thermal-cores.md):
// 208x156 uint16 LE words, frame type in word 10, frame counter in word 40; the boot sequence of
// frame types, shutter cycles (6, 1, 20) after the boot and every `shutter_period` images.
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
inline constexpr std::uint16_t kCompact = 0x0010;
inline constexpr std::uint32_t kWidth = 208;
inline constexpr std::uint32_t kHeight = 156;
inline constexpr std::uint32_t kPixels = kWidth * kHeight;  // 32448
inline constexpr std::uint32_t kFrameBytes = kPixels * 2;    // 64896
inline constexpr std::uint32_t kChunkBytes = 16224;
inline constexpr std::uint32_t kTypeWord = 10;
inline constexpr std::uint32_t kCounterWord = 40;
inline constexpr std::uint16_t kImage = 3;
inline constexpr std::uint16_t kShutter = 1;
inline constexpr std::uint16_t kStartup = 4;
// The active area a host delivers: columns 0..206, rows 1..154.
inline constexpr std::uint32_t kActiveX = 0, kActiveY = 1, kActiveWidth = 207, kActiveHeight = 154;

// Where the start-up frame has dead pixels (x, y, value), all inside the active area and apart.
struct DeadPixel {
  std::uint32_t x, y;
  std::uint16_t value;
};
inline constexpr DeadPixel kDeadPixels[] = {{17, 9, 0x0000}, {100, 77, 300}, {5, 150, 0x0000},
                                            {200, 3, 1000}, {150, 120, 0x0000}};

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
Bytes make_frame(std::uint64_t index, std::uint16_t type, std::uint16_t counter, std::uint32_t epoch);

// The active area of clamp(0x4000 + image - shutter), each dead pixel of the start-up frame the
// mean of its 4-neighbours inside the area (they are live: the dead pixels lie apart).
std::vector<std::uint16_t> expected_image(const Bytes& image, const Bytes& shutter);

}  // namespace bolo::hil::seek
