#include "seek_frames.hpp"

#include <algorithm>

namespace bolo::hil::seek {

namespace {
constexpr std::uint16_t kBoot[] = {4, 9, 14, 25, 26, 27, 28, 8, 7};
constexpr std::uint16_t kShutterCycle[] = {6, 1, 20};
constexpr std::uint16_t kShutterLevel = 7000;

void put(Bytes& f, std::uint32_t word, std::uint16_t v) {
  f[2 * word] = static_cast<std::uint8_t>(v);
  f[2 * word + 1] = static_cast<std::uint8_t>(v >> 8);
}

std::uint16_t get(const Bytes& f, std::uint32_t word) {
  return static_cast<std::uint16_t>(f[2 * word] | f[2 * word + 1] << 8);
}

// 0..2047, a different pattern for each shutter event.
std::uint16_t offset(std::uint32_t x, std::uint32_t y, std::uint32_t epoch) {
  const std::uint64_t h = (x * 0x9E3779B1ULL) ^ (y * 0x85EBCA77ULL) ^ (epoch * 0xC2B2AE3DULL + 1);
  return static_cast<std::uint16_t>((h * 0x27D4EB2FULL >> 21) & 0x7FF);
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

Bytes make_frame(const Layout& l, std::uint64_t index, std::uint16_t type, std::uint16_t counter,
                 std::uint32_t epoch) {
  Bytes f(l.frame_bytes());
  // A drifting warm spot on a gradient with per-pixel hash noise: no two frames or rows alike.
  const std::uint64_t cx = index % l.width;
  const std::uint64_t cy = (index / 2) % l.height;
  for (std::uint32_t y = 0; y < l.height; ++y)
    for (std::uint32_t x = 0; x < l.width; ++x) {
      std::uint64_t v = kShutterLevel;
      if (type == kStartup) {
        v = 8000 + ((x * 7 + y * 13) % 16 == 0 ? 12 : 0);  // mostly 8000: the driver's threshold is 7988
      } else if (type == kImage) {
        const std::int64_t dx = static_cast<std::int64_t>(x) - static_cast<std::int64_t>(cx);
        const std::int64_t dy = static_cast<std::int64_t>(y) - static_cast<std::int64_t>(cy);
        const std::uint64_t noise = (index * 0x9E3779B97F4A7C15ULL + y * 977 + x * 7919) >> 59;
        v = 8000 + 4 * y + (dx * dx + dy * dy < 225 ? 900 : 0) + noise;
      }
      if (type != kStartup) v += offset(x, y, epoch);
      put(f, y * l.width + x, static_cast<std::uint16_t>(v));
    }
  if (type == kStartup)
    for (const DeadPixel& d : l.dead) put(f, d.y * l.width + d.x, d.value);
  put(f, l.type_word, type);
  put(f, l.counter_word, counter);
  return f;
}

std::vector<std::uint16_t> expected_image(const Layout& l, const Bytes& image, const Bytes& shutter) {
  const std::uint32_t w = l.active_width, h = l.active_height;
  std::vector<std::uint16_t> out(std::size_t{w} * h);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const std::uint32_t word = (y + l.active_y) * l.width + x + l.active_x;
      const long v = 0x4000L + get(image, word) - get(shutter, word);
      out[std::size_t{y} * w + x] = static_cast<std::uint16_t>(std::clamp(v, 0L, 0xFFFFL));
    }
  for (const DeadPixel& d : l.dead) {
    const std::uint32_t x = d.x - l.active_x, y = d.y - l.active_y;
    const std::size_t at = std::size_t{y} * w + x;
    std::uint32_t sum = 0, n = 0;
    if (x > 0) sum += out[at - 1], ++n;
    if (x + 1 < w) sum += out[at + 1], ++n;
    if (y > 0) sum += out[at - w], ++n;
    if (y + 1 < h) sum += out[at + w], ++n;
    out[at] = static_cast<std::uint16_t>(sum / n);
  }
  return out;
}

}  // namespace bolo::hil::seek
