#pragma once
// Seek Thermal Compact frames as the camera sends them (../shared/docs/usb-thermal-cores.md):
// 208x156 uint16 LE words, frame type in word 10, frame counter in word 40; the boot sequence of
// frame types, shutter cycles (6, 1, 20) every `shutter_period` images, the start-up frame's dead
// pixels (0x0000 / 0xFFFF).

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

// Where the start-up frame has dead pixels (x, y, value): 3 stuck low, 2 stuck high.
struct DeadPixel {
  std::uint32_t x, y;
  std::uint16_t value;
};
inline constexpr DeadPixel kDeadPixels[] = {{17, 9, 0x0000}, {100, 77, 0xFFFF}, {5, 150, 0x0000},
                                            {200, 3, 0xFFFF}, {150, 120, 0x0000}};

// The frame-type sequence: boot frames, then images with a shutter cycle every
// `shutter_period` images.
class FrameTypes {
 public:
  explicit FrameTypes(std::uint32_t shutter_period) : period_(shutter_period) {}
  std::uint16_t next();

 private:
  std::uint32_t period_;
  std::uint64_t emitted_ = 0;
  std::uint32_t images_since_shutter_ = 0;
  int shutter_step_ = -1;  // -1: not in a shutter cycle
};

// A frame of type `type` with counter `counter`; image content from `index`.
Bytes make_frame(std::uint64_t index, std::uint16_t type, std::uint16_t counter);

}  // namespace bolo::hil::seek
