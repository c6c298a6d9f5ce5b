#pragma once
// The hardware abstraction: every source of frames (a recording, a UVC camera, a USB core) looks
// the same to the pipeline. A source pushes one frame at a time, line by line, into a LineSink.

#include <cstdint>

#include "bolo/firmware/frame_header.hpp"
#include "bolo/firmware/line_sink.hpp"

namespace bolo::hal {

enum class PixelUnits : std::uint8_t { counts, centikelvin, counts8 };

struct SourceFormat {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t bits = 16;           // significant bits of the raw counts
  PixelUnits units = PixelUnits::counts;
  std::uint32_t frame_period_ns = 0;  // nominal, 0 = unknown
};

enum class StreamStatus : std::uint8_t {
  frame,          // one whole frame was pushed into the sink
  end_of_stream,  // nothing more will come (end of a recording, device gone for good)
  fault,          // a frame was lost (timeout, short or corrupt transfer); counted, try again
};

// Faults a source survived; what it could not deliver.
struct SourceStats {
  std::uint64_t frames_delivered = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t short_transfers = 0;
  std::uint64_t corrupt_transfers = 0;
  std::uint64_t disconnects = 0;
  std::uint64_t reconnects = 0;   // the device came back after a disconnect
  std::uint64_t dropped = 0;      // frames the device numbered but never delivered (sequence gaps)
  std::uint64_t duplicates = 0;   // frames the device sent twice (same core frame counter)
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual SourceFormat format() const = 0;
  // Pushes the next frame (begin_frame, every line, end_frame) into `sink`, or nothing when the
  // status is not `frame`.
  virtual StreamStatus stream_frame(fw::LineSink& sink) = 0;
  virtual SourceStats stats() const = 0;
};

}  // namespace bolo::hal
