#include "bolo/hal/recording_player.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace bolo::hal {
namespace {

[[noreturn]] void fail(const std::filesystem::path& csv, std::uint64_t frame, const char* field,
                       const std::string& what) {
  std::ostringstream message;
  message << csv.string() << ": frame " << frame << ": field " << field << ": " << what;
  throw rec::Error(message.str());
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

PixelUnits to_pixel_units(rec::Units units) {
  switch (units) {
    case rec::Units::counts: return PixelUnits::counts;
    case rec::Units::centikelvin: return PixelUnits::centikelvin;
    case rec::Units::counts8: return PixelUnits::counts8;
  }
  return PixelUnits::counts;
}

}  // namespace

fw::FrameHeader header_from_row(const rec::FrameRow& row, std::uint32_t width,
                                std::uint32_t height, const std::filesystem::path& csv) {
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

RecordingPlayer::RecordingPlayer(const std::filesystem::path& dir) : recording_(dir) {
  const rec::RecordingInfo& info = recording_.info();
  format_.width = info.width;
  format_.height = info.height;
  format_.bits = info.bits;
  format_.units = to_pixel_units(info.units);
  if (info.fps && *info.fps > 0) format_.frame_period_ns = static_cast<std::uint32_t>(std::lround(1e9 / *info.fps));
  const std::filesystem::path csv = dir / "frames.csv";
  headers_.reserve(recording_.rows().size());
  for (const rec::FrameRow& row : recording_.rows())
    headers_.push_back(header_from_row(row, info.width, info.height, csv));
  line_.resize(info.width);
}

StreamStatus RecordingPlayer::stream_frame(fw::LineSink& sink) {
  if (next_ >= headers_.size()) return StreamStatus::end_of_stream;
  const std::uint64_t frame = next_++;
  sink.begin_frame(headers_[frame]);
  for (std::uint32_t row = 0; row < format_.height; ++row) {
    recording_.read_row(frame, row, line_);
    sink.push_line(row, fw::LineView(line_.data(), line_.size()));
  }
  sink.end_frame();
  ++stats_.frames_delivered;
  return StreamStatus::frame;
}

}  // namespace bolo::hal
