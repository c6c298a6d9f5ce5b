#include "bolo/hal/y16_frame.hpp"

namespace bolo::hal {

std::uint64_t Y16Layout::min_bytes() const {
  const std::uint64_t rows = std::uint64_t{image_rows} + telemetry_rows;
  return rows == 0 ? 0 : (rows - 1) * stride() + std::uint64_t{width} * 2;
}

bool Y16Layout::valid() const {
  return width > 0 && image_rows > 0 && stride() >= std::uint64_t{width} * 2 && width <= 0x7FFFFFFFu;
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
  for (std::uint32_t x = 0; x < layout_.width && x < out.size(); ++x) out[x] = word(row, x);
}

bool Y16Frame::telemetry(LeptonTelemetry& out) const {
  if (layout_.telemetry_rows == 0 || layout_.width < kLeptonTelemetryWords) return false;
  std::uint16_t row_a[kLeptonTelemetryWords];
  for (std::uint32_t x = 0; x < kLeptonTelemetryWords; ++x) row_a[x] = word(layout_.image_rows, x);
  return decode_lepton_telemetry(row_a, out);
}

}  // namespace bolo::hal
