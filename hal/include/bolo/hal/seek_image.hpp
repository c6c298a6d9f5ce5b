#pragma once
// What the public driver (libseek-thermal) makes of Seek frames: the active area cropped, the
// latest shutter (type 1) frame subtracted, dead pixels (found in the start-up frame) filled in.
// Protocol layer: no I/O, no exceptions, every buffer allocated at construction.
//
//   image = clamp(0x4000 + frame - shutter, 0, 0xFFFF) per pixel of the active area, then each
//   dead pixel = the mean (integer division) of its 4-neighbours known at its turn.
//
// Dead pixels (from the start-up frame, over the active area): a histogram of the values in
// [0, 0x4000), one bin per value, bin 0 ignored; m = the most populated bin (the lowest of a tie),
// M = the area's maximum; a pixel is dead when its value <= m - (M - m). They are filled in
// passes in row order, each taking the first dead pixel with a known (live or already filled)
// neighbour, so every filled pixel has one. A dead pixel with no live pixel in reach (all of
// the area dead) is left as it is and counted in `unfillable_pixels()`.

#include <cstdint>
#include <span>
#include <vector>

#include "bolo/hal/seek_frame_parser.hpp"

namespace bolo::hal {

inline constexpr std::uint16_t kSeekShutterOffset = 0x4000;

class SeekImageCorrector {
 public:
  explicit SeekImageCorrector(const SeekModel& model);
  const SeekCrop& crop() const { return crop_; }

  // Start-up frame (whole raw frame, host-endian words): the dead-pixel map and fill order.
  void take_startup(std::span<const std::uint16_t> frame);
  // Shutter frame: kept (its active area) for the subtraction.
  void take_shutter(std::span<const std::uint16_t> frame);
  bool has_shutter() const { return has_shutter_; }
  // Forgets the shutter frame and the dead pixels (a camera that boots again).
  void reset();

  // An image frame into image(): subtracted (when `subtract_shutter` and a shutter frame is
  // kept), dead pixels filled.
  void correct(std::span<const std::uint16_t> frame, bool subtract_shutter);
  std::span<const std::uint16_t> image() const { return image_; }

  // 1 = dead, one byte per active pixel, row by row.
  std::span<const std::uint8_t> dead_map() const { return dead_; }
  std::uint32_t dead_pixels() const { return dead_count_; }
  std::uint32_t unfillable_pixels() const { return unfillable_; }

 private:
  // A dead pixel in fill order, with the neighbours known at its turn (bits: left, right, up, down).
  struct Fill {
    std::uint32_t index;
    std::uint8_t neighbours;
  };
  void copy_active(std::span<const std::uint16_t> frame, std::vector<std::uint16_t>& out) const;
  std::uint8_t known_neighbours(std::uint32_t x, std::uint32_t y) const;

  SeekModel model_;
  SeekCrop crop_;
  std::vector<std::uint16_t> shutter_;
  std::vector<std::uint16_t> image_;
  std::vector<std::uint8_t> dead_;
  std::vector<std::uint8_t> known_;     // scratch while the fill order is built
  std::vector<std::uint32_t> histogram_;
  std::vector<Fill> fill_;
  std::size_t fill_size_ = 0;
  std::uint32_t dead_count_ = 0;
  std::uint32_t unfillable_ = 0;
  bool has_shutter_ = false;
};

}  // namespace bolo::hal
