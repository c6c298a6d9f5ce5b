#include "seek_frames.hpp"

namespace bolo::hil::seek {

namespace {
constexpr std::uint16_t kBoot[] = {4, 9, 14, 25, 26, 27, 28, 8, 7};
constexpr std::uint16_t kShutterCycle[] = {6, 1, 20};

void put(Bytes& f, std::uint32_t word, std::uint16_t v) {
  f[2 * word] = static_cast<std::uint8_t>(v);
  f[2 * word + 1] = static_cast<std::uint8_t>(v >> 8);
}
}  // namespace

std::uint16_t FrameTypes::next() {
  const std::uint64_t i = emitted_++;
  if (i < std::size(kBoot)) return kBoot[i];
  if (shutter_step_ >= 0) {
    const std::uint16_t t = kShutterCycle[shutter_step_];
    shutter_step_ = shutter_step_ + 1 < static_cast<int>(std::size(kShutterCycle)) ? shutter_step_ + 1 : -1;
    return t;
  }
  if (period_ > 0 && images_since_shutter_ == period_) {
    images_since_shutter_ = 0;
    shutter_step_ = 1;
    return kShutterCycle[0];
  }
  ++images_since_shutter_;
  return kImage;
}

Bytes make_frame(std::uint64_t index, std::uint16_t type, std::uint16_t counter) {
  Bytes f(kFrameBytes);
  // A drifting warm spot on a gradient with per-pixel hash noise: no two frames or rows alike.
  const std::uint64_t cx = index % kWidth;
  const std::uint64_t cy = (index / 2) % kHeight;
  for (std::uint32_t y = 0; y < kHeight; ++y)
    for (std::uint32_t x = 0; x < kWidth; ++x) {
      const std::int64_t dx = static_cast<std::int64_t>(x) - static_cast<std::int64_t>(cx);
      const std::int64_t dy = static_cast<std::int64_t>(y) - static_cast<std::int64_t>(cy);
      const std::uint64_t noise = (index * 0x9E3779B97F4A7C15ULL + y * 977 + x * 7919) >> 59;
      const std::uint64_t v = 8000 + 4 * y + (dx * dx + dy * dy < 225 ? 900 : 0) + noise;
      put(f, y * kWidth + x, static_cast<std::uint16_t>(v));
    }
  if (type == kStartup)
    for (const DeadPixel& d : kDeadPixels) put(f, d.y * kWidth + d.x, d.value);
  put(f, kTypeWord, type);
  put(f, kCounterWord, counter);
  return f;
}

}  // namespace bolo::hil::seek
