#pragma once
// The emulated PureThermal's frames: images from a recording in the shared format (160x120,
// played with the project's RecordingPlayer and looped), or simulated ones, as Y16 little-endian
// rows; on the 160x122 frame two Lepton telemetry rows follow the image (row A: frame counter,
// uptime, FFC state and time, FPA and housing temperatures; row B zero).

#include <cstdint>
#include <string>
#include <vector>

#include "uvc_control.hpp"

namespace bolo::hil::uvc {

using Bytes = std::vector<std::uint8_t>;

struct Telemetry {
  std::uint32_t frame_counter = 0;
  std::uint32_t uptime_ms = 0;
  std::uint32_t time_at_last_ffc_ms = 0;
  std::uint16_t fpa_temp_ck = 30000;      // 26.85 °C
  std::uint16_t housing_temp_ck = 30150;  // 28.35 °C
};

// Row A's 80 words for `t` (the rest of the 160-word row is zero).
std::vector<std::uint16_t> telemetry_row_a(const Telemetry& t);

class FrameFeed {
 public:
  // `recording`: a folder in the shared format with 160x120 frames; empty: simulated images.
  // Throws naming the folder when it cannot be played or has another size.
  explicit FrameFeed(const std::string& recording);
  std::uint64_t images() const { return images_.size() / kPixels; }
  // Frame `index` (the recording's image index % images()) at `size`, telemetry rows from `t`.
  Bytes frame(std::uint64_t index, FrameSize size, const Telemetry& t) const;

  static constexpr std::uint32_t kWidth = 160, kHeight = 120, kPixels = kWidth * kHeight;

 private:
  std::vector<std::uint16_t> images_;  // images() x 120 x 160
};

// FNV-1a over bytes (the send log's hashes).
std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size);

}  // namespace bolo::hil::uvc
