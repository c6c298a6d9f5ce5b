#include "bolo/recording/frame_row_header.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

namespace bolo::rec {
namespace {

[[noreturn]] void fail(const std::filesystem::path& csv, std::uint64_t frame, const char* field,
                       const std::string& what) {
  std::ostringstream message;
  message << csv.string() << ": frame " << frame << ": field " << field << ": " << what;
  throw Error(message.str());
}

std::uint32_t duration_ns(const std::optional<double>& seconds, const std::filesystem::path& csv,
                          std::uint64_t frame, const char* field) {
  if (!seconds) return 0;
  const double ns = std::round(*seconds * 1e9);
  if (!(ns >= 0) || ns > double{std::numeric_limits<std::uint32_t>::max()})
    fail(csv, frame, field, "out of range for the firmware (0 to 4.29 s)");
  return static_cast<std::uint32_t>(ns);
}

std::int32_t milli_celsius(const std::optional<double>& celsius) {
  if (!celsius || !std::isfinite(*celsius) || std::abs(*celsius) > 1e6)
    return fw::kUnknownTemperature;
  return static_cast<std::int32_t>(std::lround(*celsius * 1000.0));
}

std::optional<double> celsius(std::int32_t mc) {
  if (mc == fw::kUnknownTemperature) return std::nullopt;
  return std::round(mc / 10.0) / 100.0;  // the format keeps 0.01 °C
}

}  // namespace

fw::FrameHeader header_from_row(const FrameRow& row, std::uint32_t width, std::uint32_t height,
                                const std::filesystem::path& csv) {
  fw::FrameHeader header;
  header.width = width;
  header.height = height;
  header.sequence = row.index;
  header.sequence_valid = true;
  if (row.t_s) {
    const double ns = std::round(*row.t_s * 1e9);
    if (!(std::abs(ns) < 9.2e18)) fail(csv, row.index, "t_s", "out of range");
    header.timestamp_ns = static_cast<std::int64_t>(ns);
    header.timestamp_valid = true;
  }
  header.exposure_ns = duration_ns(row.exposure_s, csv, row.index, "exposure_s");
  header.readout_ns = duration_ns(row.readout_s, csv, row.index, "readout_s");
  header.ffc = !row.ffc ? fw::FfcState::unknown
                        : (*row.ffc ? fw::FfcState::completed : fw::FfcState::none);
  header.fpa_temp_mc = milli_celsius(row.fpa_temp_c);
  header.housing_temp_mc = milli_celsius(row.housing_temp_c);
  return header;
}

FrameRow row_from_header(const fw::FrameHeader& header, std::uint64_t index, std::int64_t t0_ns) {
  FrameRow row;
  row.index = index;
  if (header.timestamp_valid)
    row.t_s = static_cast<double>(header.timestamp_ns - t0_ns) / 1e9;  // division: 1.14065, not 1.1406500000000002
  if (header.exposure_ns != 0) row.exposure_s = header.exposure_ns * 1e-9;
  if (header.readout_ns != 0) row.readout_s = header.readout_ns * 1e-9;
  if (header.ffc != fw::FfcState::unknown) row.ffc = fw::shutter_event(header.ffc);
  row.fpa_temp_c = celsius(header.fpa_temp_mc);
  row.housing_temp_c = celsius(header.housing_temp_mc);
  return row;
}

FrameRow RowClock::row(const fw::FrameHeader& header, std::uint64_t index) {
  fw::FrameHeader stamped = header;
  if (header.timestamp_valid) {
    if (!t0_) t0_ = header.timestamp_ns;
    if (last_ && header.timestamp_ns <= *last_) {
      ++not_increasing_;
      stamped.timestamp_valid = false;
    } else {
      last_ = header.timestamp_ns;
    }
  }
  return row_from_header(stamped, index, t0_.value_or(0));
}

}  // namespace bolo::rec
