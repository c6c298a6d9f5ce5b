#include "bolo/hal/raw_stream_source.hpp"

#include <cerrno>
#include <cstddef>

#include <unistd.h>

namespace bolo::hal {

RawStreamSource::RawStreamSource(int fd, const RawStreamConfig& config,
                                 std::span<std::uint8_t> frame, std::span<fw::Pixel> line)
    : fd_(fd), config_(config) {
  if (frame.size() >= frame_bytes(config) && line.size() >= config.width) {
    bytes_ = frame.first(frame_bytes(config));
    line_ = line.first(config.width);
  }
}

SourceFormat RawStreamSource::format() const {
  SourceFormat f;
  f.width = config_.width;
  f.height = config_.height;
  f.bits = config_.bits;
  f.frame_period_ns = config_.frame_period_ns;
  return f;
}

StreamStatus RawStreamSource::stream_frame(fw::LineSink& sink) {
  if (ended_ || bytes_.empty()) return StreamStatus::end_of_stream;
  std::size_t have = 0;
  while (have < bytes_.size()) {
    const ssize_t n = ::read(fd_, bytes_.data() + have, bytes_.size() - have);
    if (n > 0) {
      have += static_cast<std::size_t>(n);
    } else if (n == 0) {
      break;
    } else if (errno != EINTR) {
      ++stats_.corrupt_transfers;
      ended_ = true;
      return StreamStatus::end_of_stream;
    }
  }
  if (have < bytes_.size()) {
    if (have > 0) ++stats_.short_transfers;
    ended_ = true;
    return StreamStatus::end_of_stream;
  }

  fw::FrameHeader header;
  header.width = config_.width;
  header.height = config_.height;
  header.sequence = next_;
  header.sequence_valid = true;
  if (config_.frame_period_ns != 0) {
    header.timestamp_ns = static_cast<std::int64_t>(next_) * config_.frame_period_ns;
    header.timestamp_valid = true;
  }
  header.exposure_ns = config_.exposure_ns;
  header.readout_ns = config_.readout_ns;
  sink.begin_frame(header);
  const std::uint8_t* p = bytes_.data();
  for (std::uint32_t row = 0; row < config_.height; ++row) {
    for (std::uint32_t x = 0; x < config_.width; ++x, p += 2)
      line_[x] = static_cast<fw::Pixel>(p[0] | (p[1] << 8));  // little-endian on every host
    sink.push_line(row, fw::LineView(line_.data(), line_.size()));
  }
  sink.end_frame();
  ++next_;
  ++stats_.frames_delivered;
  return StreamStatus::frame;
}

}  // namespace bolo::hal
