#include "uvc_frames.hpp"

#include <stdexcept>

#include "bolo/core/frame_collector.hpp"
#include "bolo/hal/recording_player.hpp"
#include "fnv1a.hpp"

namespace bolo::hil::uvc {

namespace {

// A moving diagonal ramp with the frame number in it: every simulated frame differs.
void simulate(std::vector<std::uint16_t>& out, std::uint64_t frames) {
  for (std::uint64_t f = 0; f < frames; ++f)
    for (std::uint32_t y = 0; y < FrameFeed::kHeight; ++y)
      for (std::uint32_t x = 0; x < FrameFeed::kWidth; ++x)
        out.push_back(static_cast<std::uint16_t>(7000 + ((x + 2 * y + 3 * f) % 1024) + (x == 0 && y == 0 ? f : 0)));
}

}  // namespace

std::vector<std::uint16_t> telemetry_row_a(const Telemetry& t) {
  std::vector<std::uint16_t> a(80, 0);
  auto u32 = [&](std::size_t at, std::uint32_t v) {
    a[at] = static_cast<std::uint16_t>(v & 0xFFFF);  // low word first
    a[at + 1] = static_cast<std::uint16_t>(v >> 16);
  };
  a[0] = 14;  // telemetry revision
  u32(1, t.uptime_ms);
  u32(3, 3u << 4);  // FFC state: complete
  u32(20, t.frame_counter);
  a[23] = 8000;  // FPA counts
  a[24] = t.fpa_temp_ck;
  a[26] = t.housing_temp_ck;
  a[29] = t.fpa_temp_ck;
  u32(30, t.time_at_last_ffc_ms);
  return a;
}

FrameFeed::FrameFeed(const std::string& recording) {
  if (recording.empty()) {
    simulate(images_, 64);
    return;
  }
  hal::RecordingPlayer player(recording);
  const hal::SourceFormat f = player.format();
  if (f.width != kWidth || f.height != kHeight)
    throw std::runtime_error(recording + ": the recording is " + std::to_string(f.width) + "x" +
                             std::to_string(f.height) + "; the emulated PureThermal streams 160x120");
  std::vector<std::uint16_t> frame(fw::FrameCollector::storage_pixels(kWidth, kHeight));
  fw::FrameCollector sink(kWidth, kHeight, frame);
  while (player.stream_frame(sink) == hal::StreamStatus::frame && sink.complete())
    images_.insert(images_.end(), frame.begin(), frame.end());
  if (images_.empty()) throw std::runtime_error(recording + ": no whole frame played");
  if (!sink.complete()) throw std::runtime_error(recording + ": a played frame was not whole");
}

Bytes FrameFeed::frame(std::uint64_t index, FrameSize size, const Telemetry& t) const {
  if (size.width != kWidth || size.height < kHeight)
    throw std::runtime_error("frame size " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                             " is not the PureThermal's");
  Bytes out(size.bytes(), 0);
  const std::uint16_t* image = images_.data() + (index % images()) * kPixels;
  for (std::uint32_t i = 0; i < kPixels; ++i) {
    out[2 * i] = static_cast<std::uint8_t>(image[i] & 0xFF);
    out[2 * i + 1] = static_cast<std::uint8_t>(image[i] >> 8);
  }
  if (size.height > kHeight) {
    const std::vector<std::uint16_t> a = telemetry_row_a(t);
    for (std::size_t x = 0; x < a.size(); ++x) {
      out[2 * kPixels + 2 * x] = static_cast<std::uint8_t>(a[x] & 0xFF);
      out[2 * kPixels + 2 * x + 1] = static_cast<std::uint8_t>(a[x] >> 8);
    }
  }
  return out;
}

std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size) { return hil::fnv1a_add(hil::kFnvOffset, data, size); }

}  // namespace bolo::hil::uvc
