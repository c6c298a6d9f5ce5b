#include "bolo/hal/recording_player.hpp"

#include <cmath>

#include "bolo/recording/frame_row_header.hpp"

namespace bolo::hal {
namespace {

PixelUnits to_pixel_units(rec::Units units) {
  switch (units) {
    case rec::Units::counts: return PixelUnits::counts;
    case rec::Units::centikelvin: return PixelUnits::centikelvin;
    case rec::Units::counts8: return PixelUnits::counts8;
  }
  return PixelUnits::counts;
}

}  // namespace

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
    headers_.push_back(rec::header_from_row(row, info.width, info.height, csv));
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
