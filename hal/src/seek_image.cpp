#include "bolo/hal/seek_image.hpp"

#include <algorithm>
#include <cstring>

namespace bolo::hal {
namespace {
constexpr std::uint8_t kLeft = 1, kRight = 2, kUp = 4, kDown = 8;
constexpr std::size_t kHistogramBins = 0x4000;
}  // namespace

SeekImageCorrector::SeekImageCorrector(const SeekModel& model)
    : model_(model),
      crop_(model.crop),
      shutter_(model.crop.pixels()),
      image_(model.crop.pixels()),
      dead_(model.crop.pixels()),
      known_(model.crop.pixels()),
      histogram_(kHistogramBins),
      fill_(model.crop.pixels()) {}

void SeekImageCorrector::reset() {
  has_shutter_ = false;
  std::fill(dead_.begin(), dead_.end(), std::uint8_t{0});
  fill_size_ = 0;
  dead_count_ = 0;
  unfillable_ = 0;
}

void SeekImageCorrector::copy_active(std::span<const std::uint16_t> frame, std::vector<std::uint16_t>& out) const {
  for (std::uint32_t y = 0; y < crop_.height; ++y)
    std::memcpy(&out[std::size_t{y} * crop_.width], &frame[std::size_t{y + crop_.y} * model_.width + crop_.x],
                crop_.width * sizeof(std::uint16_t));
}

void SeekImageCorrector::take_shutter(std::span<const std::uint16_t> frame) {
  copy_active(frame, shutter_);
  has_shutter_ = true;
}

std::uint8_t SeekImageCorrector::known_neighbours(std::uint32_t x, std::uint32_t y) const {
  const std::size_t i = std::size_t{y} * crop_.width + x;
  std::uint8_t mask = 0;
  if (x > 0 && known_[i - 1]) mask |= kLeft;
  if (x + 1 < crop_.width && known_[i + 1]) mask |= kRight;
  if (y > 0 && known_[i - crop_.width]) mask |= kUp;
  if (y + 1 < crop_.height && known_[i + crop_.width]) mask |= kDown;
  return mask;
}

void SeekImageCorrector::take_startup(std::span<const std::uint16_t> frame) {
  // The start-up frame's active area, through image_ as scratch.
  copy_active(frame, image_);
  std::fill(histogram_.begin(), histogram_.end(), 0u);
  std::uint16_t maximum = 0;
  for (std::uint16_t v : image_) {
    if (v < kHistogramBins) ++histogram_[v];
    maximum = std::max(maximum, v);
  }
  histogram_[0] = 0;
  const std::int64_t mode = std::max_element(histogram_.begin(), histogram_.end()) - histogram_.begin();
  const std::int64_t threshold = mode - (std::int64_t{maximum} - mode);
  dead_count_ = 0;
  for (std::size_t i = 0; i < image_.size(); ++i) {
    dead_[i] = image_[i] <= threshold ? 1 : 0;
    known_[i] = dead_[i] ? 0 : 1;
    dead_count_ += dead_[i];
  }
  // Passes in row order until every dead pixel is listed, or a pass lists none.
  fill_size_ = 0;
  std::uint32_t pending = dead_count_;
  for (bool progress = true; pending > 0 && progress;) {
    progress = false;
    for (std::uint32_t y = 0; y < crop_.height; ++y)
      for (std::uint32_t x = 0; x < crop_.width; ++x) {
        const std::size_t i = std::size_t{y} * crop_.width + x;
        if (known_[i]) continue;
        const std::uint8_t neighbours = known_neighbours(x, y);
        if (neighbours == 0) continue;
        fill_[fill_size_++] = {static_cast<std::uint32_t>(i), neighbours};
        known_[i] = 1;
        --pending;
        progress = true;
      }
  }
  unfillable_ = pending;
}

void SeekImageCorrector::correct(std::span<const std::uint16_t> frame, bool subtract_shutter) {
  copy_active(frame, image_);
  if (subtract_shutter && has_shutter_)
    for (std::size_t i = 0; i < image_.size(); ++i) {
      const std::int32_t v = std::int32_t{kSeekShutterOffset} + image_[i] - shutter_[i];
      image_[i] = static_cast<std::uint16_t>(std::clamp(v, 0, 0xFFFF));
    }
  const std::size_t w = crop_.width;
  for (std::size_t k = 0; k < fill_size_; ++k) {
    const Fill f = fill_[k];
    std::uint32_t sum = 0, count = 0;
    auto add = [&](std::uint8_t side, std::size_t at) {
      if ((f.neighbours & side) == 0) return;
      sum += image_[at];
      ++count;
    };
    add(kLeft, f.index - 1);
    add(kRight, f.index + 1);
    add(kUp, f.index - w);
    add(kDown, f.index + w);
    if (count > 0) image_[f.index] = static_cast<std::uint16_t>(sum / count);  // always: listed with one
  }
}

}  // namespace bolo::hal
