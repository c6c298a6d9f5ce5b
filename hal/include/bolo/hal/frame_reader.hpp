#pragma once
// Whole frames from any source, as every command that reads one needs them: a frame the device
// faulted on (timeout, short or corrupt transfer) or delivered incomplete is skipped and counted,
// and the caller gives up after too many in a row. Plus what a command says about the source
// afterwards (its fault counters) and what a recording made from it records (size, bit depth).
// Host code.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "bolo/core/frame_source.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::hal {

class FrameReader {
 public:
  enum class Result { frame, ended, gave_up, stopped };

  FrameReader(FrameSource& source, std::uint64_t max_faults) : source_(source), max_faults_(max_faults) {}

  // Pushes the next whole frame into `sink`: `frame`; `ended` when the source has no more;
  // `gave_up` after more than max_faults faulted or incomplete frames in a row. A skipped frame
  // may have left part of itself in `sink` (a stage then sees an incomplete predecessor).
  Result next(fw::LineSink& sink);
  // Asked after each faulted frame: true makes `next` return `stopped` instead of trying again (a
  // stop requested while a silent camera times out). Unset: never.
  void set_stop(std::function<bool()> stop) { stop_ = std::move(stop); }
  // The header of the last frame `next` delivered.
  const fw::FrameHeader& header() const { return tracker_.header; }
  std::uint64_t frames() const { return frames_; }
  std::uint64_t skipped() const { return skipped_; }

 private:
  // Forwards to the sink and notes whether every row came once, in order, and the frame ended.
  struct Tracker final : fw::LineSink {
    fw::LineSink* sink = nullptr;
    fw::FrameHeader header;
    std::uint32_t next_row = 0;
    bool ended = false, in_order = true;
    void begin_frame(const fw::FrameHeader& h) override;
    void push_line(std::uint32_t row, fw::LineView line) override;
    void push_lines(std::uint32_t first_row, std::uint32_t count, const fw::Pixel* pixels, std::size_t width,
                    std::size_t stride) override;
    void end_frame() override;
    bool complete() const { return ended && in_order && next_row == header.height; }
  };

  FrameSource& source_;
  std::uint64_t max_faults_;
  std::function<bool()> stop_;
  Tracker tracker_;
  std::uint64_t frames_ = 0, skipped_ = 0;
};

// "timeouts 0, short 0, corrupt 0, disconnects 0, reconnects 0, dropped 0, duplicates 0".
std::string stats_text(const SourceStats& stats);
// "skipped in camera 2, counter jumps 0" (empty when the source keeps none).
std::string extra_counters_text(const ExtraCounters& counters);
// stats_text, then "; device counters: ..." where the source keeps any.
std::string fault_text(const FrameSource& source);
// What a recording of the source records about it (capture.json): the spec, SourceStats, the
// extra counters and the frames whose time stamp was not after the previous one.
nlohmann::json source_record(std::string_view spec, const FrameSource& source,
                             std::uint64_t timestamps_not_increasing);

// recording.json of frames from `source`: sensor, size, bit depth, units, nominal fps.
rec::RecordingInfo recording_info_of(const OpenedSource& source);

}  // namespace bolo::hal
