#pragma once
// The hardware abstraction: every source of frames (a recording, a UVC camera, a USB core) looks
// the same to the pipeline. A source pushes one frame at a time, line by line, into a LineSink.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "bolo/core/frame_header.hpp"
#include "bolo/core/line_sink.hpp"

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

// A counter a source keeps beyond SourceStats (what only that kind of device can tell, e.g. frames
// a camera skipped internally). The name is snake_case and stable: `bolo capture` writes it as a
// key of capture.json. It must outlive the source (a string literal).
struct NamedCounter {
  std::string_view name;
  std::uint64_t value = 0;
};

// The extra counters of one source, in a fixed order per kind of source, zeros included (which
// counters a source keeps says what it can detect). Fixed capacity so a board build reports them
// without allocating; a source (with any wrapper's own) stays well below it, which the tests check.
class ExtraCounters {
 public:
  static constexpr std::size_t kCapacity = 16;
  // Beyond kCapacity the counter is not kept.
  void add(std::string_view name, std::uint64_t value) {
    if (size_ < kCapacity) items_[size_++] = {name, value};
  }
  void add(const ExtraCounters& other) {
    for (const NamedCounter& c : other.items()) add(c.name, c.value);
  }
  std::span<const NamedCounter> items() const { return {items_.data(), size_}; }
  // The counter called `name`, or null when the source does not keep one.
  const NamedCounter* find(std::string_view name) const {
    for (const NamedCounter& c : items())
      if (c.name == name) return &c;
    return nullptr;
  }

 private:
  std::array<NamedCounter, kCapacity> items_{};
  std::size_t size_ = 0;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual SourceFormat format() const = 0;
  // Pushes the next frame (begin_frame, every line, end_frame) into `sink`, or nothing when the
  // status is not `frame`.
  virtual StreamStatus stream_frame(fw::LineSink& sink) = 0;
  virtual SourceStats stats() const = 0;
  // What the source counts beyond SourceStats; none unless the device tells more.
  virtual ExtraCounters extra_counters() const { return {}; }
};

}  // namespace bolo::hal
