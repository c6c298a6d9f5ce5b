#include "bolo/hal/frame_reader.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace bolo::hal {

void FrameReader::Tracker::begin_frame(const fw::FrameHeader& h) {
  header = h;
  next_row = 0;
  ended = false;
  in_order = true;
  sink->begin_frame(h);
}

void FrameReader::Tracker::push_line(std::uint32_t row, fw::LineView line) {
  in_order = in_order && row == next_row;
  next_row = row + 1;
  sink->push_line(row, line);
}

void FrameReader::Tracker::push_lines(std::uint32_t first_row, std::uint32_t count, const fw::Pixel* pixels,
                                      std::size_t width, std::size_t stride) {
  in_order = in_order && first_row == next_row;
  next_row = first_row + count;
  sink->push_lines(first_row, count, pixels, width, stride);
}

void FrameReader::Tracker::end_frame() {
  ended = true;
  sink->end_frame();
}

FrameReader::Result FrameReader::next(fw::LineSink& sink) {
  tracker_.sink = &sink;
  std::uint64_t in_a_row = 0;
  for (;;) {
    tracker_.ended = false;
    const StreamStatus s = source_.stream_frame(tracker_);
    if (s == StreamStatus::end_of_stream) return Result::ended;
    if (s == StreamStatus::frame && tracker_.complete()) {
      ++frames_;
      return Result::frame;
    }
    ++skipped_;
    if (++in_a_row > max_faults_) return Result::gave_up;
    if (stop_ && stop_()) return Result::stopped;
  }
}

std::string stats_text(const SourceStats& stats) {
  std::ostringstream o;
  o << "timeouts " << stats.timeouts << ", short " << stats.short_transfers << ", corrupt " << stats.corrupt_transfers
    << ", disconnects " << stats.disconnects << ", reconnects " << stats.reconnects << ", dropped " << stats.dropped
    << ", duplicates " << stats.duplicates;
  return o.str();
}

// "skipped_in_camera 2" reads as "skipped in camera 2", like the SourceStats line beside it.
std::string extra_counters_text(const ExtraCounters& counters) {
  std::ostringstream o;
  for (const NamedCounter& c : counters.items()) {
    std::string name(c.name);
    std::replace(name.begin(), name.end(), '_', ' ');
    o << (o.tellp() > 0 ? ", " : "") << name << " " << c.value;
  }
  return o.str();
}

std::string fault_text(const FrameSource& source) {
  const ExtraCounters counters = source.extra_counters();
  const std::string extra = counters.items().empty() ? "" : "; device counters: " + extra_counters_text(counters);
  return stats_text(source.stats()) + extra;
}

nlohmann::json source_record(std::string_view spec, const FrameSource& source,
                             std::uint64_t timestamps_not_increasing) {
  const SourceStats s = source.stats();
  // items() views into the ExtraCounters: it must outlive the loop.
  const ExtraCounters extra = source.extra_counters();
  nlohmann::json counters = nlohmann::json::object();
  for (const NamedCounter& c : extra.items()) counters[std::string(c.name)] = c.value;
  return {{"device", std::string(spec)},
          {"stats", {{"frames_delivered", s.frames_delivered}, {"timeouts", s.timeouts},
                     {"short_transfers", s.short_transfers},   {"corrupt_transfers", s.corrupt_transfers},
                     {"disconnects", s.disconnects},           {"reconnects", s.reconnects},
                     {"dropped", s.dropped},                   {"duplicates", s.duplicates}}},
          {"extra_counters", counters},
          {"timestamps_not_increasing", timestamps_not_increasing}};
}

rec::RecordingInfo recording_info_of(const OpenedSource& source) {
  const SourceFormat format = source.format();
  rec::RecordingInfo info;
  info.sensor = source.sensor();
  info.width = format.width;
  info.height = format.height;
  info.bits = format.bits;
  switch (format.units) {
    case PixelUnits::centikelvin: info.units = rec::Units::centikelvin; break;
    case PixelUnits::counts8: info.units = rec::Units::counts8; break;
    case PixelUnits::counts: info.units = rec::Units::counts; break;
  }
  if (format.frame_period_ns != 0) info.fps = std::round(1e11 / format.frame_period_ns) / 100.0;
  return info;
}

}  // namespace bolo::hal
