#pragma once
// Raw Y16 frames (width x height little-endian uint16, back to back) from a file descriptor: a
// pipe from a capture tool, a FIFO, a file. Board-safe: no exceptions, one frame buffer sized at
// construction (or the caller's), POSIX read(2). Timing comes from the configuration (a raw
// stream carries none).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "bolo/core/frame_source.hpp"

namespace bolo::hal {

struct RawStreamConfig {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t bits = 16;
  std::uint32_t frame_period_ns = 0;  // timestamps = index * period; 0 = none
  std::uint32_t exposure_ns = 0;
  std::uint32_t readout_ns = 0;
};

class RawStreamSource final : public FrameSource {
 public:
  // Does not own `fd`. Allocates its one frame buffer here, never afterwards.
  RawStreamSource(int fd, const RawStreamConfig& config);
  // The caller's storage instead, no allocation: `frame` of at least frame_bytes(config) bytes and
  // `line` of at least config.width pixels (smaller storage: a source that ends at once).
  RawStreamSource(int fd, const RawStreamConfig& config, std::span<std::uint8_t> frame,
                  std::span<fw::Pixel> line);
  RawStreamSource(const RawStreamSource&) = delete;  // the views may point at owned storage
  RawStreamSource& operator=(const RawStreamSource&) = delete;
  static constexpr std::size_t frame_bytes(const RawStreamConfig& config) {
    return std::size_t{config.width} * config.height * 2;
  }
  SourceFormat format() const override;
  // end_of_stream at EOF; a frame cut short by EOF counts as a short transfer and ends the
  // stream; a read error other than EINTR counts as a fault and ends the stream too.
  StreamStatus stream_frame(fw::LineSink& sink) override;
  SourceStats stats() const override { return stats_; }

 private:
  int fd_;
  RawStreamConfig config_;
  std::vector<std::uint8_t> owned_bytes_;  // empty with the caller's storage
  std::vector<fw::Pixel> owned_line_;
  std::span<std::uint8_t> bytes_;  // one frame
  std::span<fw::Pixel> line_;      // one line
  std::uint64_t next_ = 0;
  bool ended_ = false;
  SourceStats stats_;
};

}  // namespace bolo::hal
