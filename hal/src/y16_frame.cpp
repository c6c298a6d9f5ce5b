#include "bolo/hal/y16_frame.hpp"

namespace bolo::hal {

std::uint32_t bytes_per_pixel(V4l2Pixels pixels) { return pixels == V4l2Pixels::grey ? 1u : 2u; }

std::uint64_t Y16Layout::min_bytes() const {
  const std::uint64_t rows = std::uint64_t{image_rows} + telemetry_rows;
  return rows == 0 ? 0 : (rows - 1) * stride() + std::uint64_t{width} * bytes_per_pixel(pixels);
}

bool Y16Layout::valid() const {
  const bool telemetry_fits = telemetry_rows == 0 || pixels == V4l2Pixels::y16;
  return width > 0 && image_rows > 0 && width <= 0x7FFFFFFFu && telemetry_fits &&
         stride() >= std::uint64_t{width} * bytes_per_pixel(pixels);
}

Y16Check Y16Frame::check(std::span<const std::uint8_t> bytes, const Y16Layout& layout) {
  if (!layout.valid()) return Y16Check::bad_layout;
  return bytes.size() < layout.min_bytes() ? Y16Check::short_frame : Y16Check::ok;
}

std::uint16_t Y16Frame::word(std::uint32_t row, std::uint32_t x) const {
  const std::size_t at = std::size_t{row} * layout_.stride() + std::size_t{x} * 2;
  return static_cast<std::uint16_t>(bytes_[at] | (bytes_[at + 1] << 8));
}

void Y16Frame::image_row(std::uint32_t row, std::span<std::uint16_t> out) const {
  const std::uint32_t n = layout_.width < out.size() ? layout_.width : static_cast<std::uint32_t>(out.size());
  const std::uint8_t* line = bytes_.data() + std::size_t{row} * layout_.stride();
  switch (layout_.pixels) {
    case V4l2Pixels::y16:
      for (std::uint32_t x = 0; x < n; ++x) out[x] = word(row, x);
      break;
    case V4l2Pixels::grey:
      for (std::uint32_t x = 0; x < n; ++x) out[x] = line[x];
      break;
    case V4l2Pixels::yuyv:  // Y0 U Y1 V: luma at even bytes
      for (std::uint32_t x = 0; x < n; ++x) out[x] = line[2 * static_cast<std::size_t>(x)];
      break;
    case V4l2Pixels::uyvy:  // U Y0 V Y1: luma at odd bytes
      for (std::uint32_t x = 0; x < n; ++x) out[x] = line[2 * static_cast<std::size_t>(x) + 1];
      break;
  }
}

bool Y16Frame::telemetry(LeptonTelemetry& out) const {
  if (layout_.telemetry_rows == 0 || layout_.width < kLeptonTelemetryWords) return false;
  std::uint16_t row_a[kLeptonTelemetryWords];
  for (std::uint32_t x = 0; x < kLeptonTelemetryWords; ++x) row_a[x] = word(layout_.image_rows, x);
  return decode_lepton_telemetry(row_a, out);
}

}  // namespace bolo::hal
