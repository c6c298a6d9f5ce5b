#include "bolo/recording_source.hpp"

#include <memory>

#include "bolo/core/frame_collector.hpp"
#include "bolo/errors.hpp"
#include "bolo/hal/frame_reader.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/recording/frame_row_header.hpp"

namespace bolo::cli {

std::optional<std::filesystem::path> recording_folder_or_live(const std::string& spec, bool frames_given) {
  try {
    const hal::SourceSpec parsed = hal::parse_source_spec(spec);
    if (parsed.backend.scheme == "file") {
      hal::require_recording_folder(parsed.argument);
      return std::filesystem::path(parsed.argument);
    }
    if (!parsed.backend.finite && !frames_given) fail("--frames: required for a live camera (", spec, ")");
    if (!parsed.backend.unavailable.empty()) fail(spec, ": ", parsed.backend.unavailable);
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
  return std::nullopt;
}

odo::LiveFrames read_live_frames(const std::string& spec, std::optional<std::uint64_t> max_frames,
                                 std::uint64_t max_faults) {
  std::unique_ptr<hal::OpenedSource> source;
  try {
    source = hal::open_source(spec);
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
  odo::LiveFrames frames;
  frames.name = spec;
  const hal::SourceFormat format = source->format();
  frames.width = format.width, frames.height = format.height;
  frames.units = hal::recording_info_of(*source).units;
  std::vector<fw::Pixel> storage(fw::FrameCollector::storage_pixels(format.width, format.height));
  fw::FrameCollector grab(format.width, format.height, storage);
  hal::FrameReader reader(*source, max_faults);
  rec::RowClock clock;
  for (std::uint64_t i = 0; !max_frames || i < *max_frames; ++i) {
    const hal::FrameReader::Result r = reader.next(grab);
    if (r == hal::FrameReader::Result::ended) break;
    if (r == hal::FrameReader::Result::gave_up)
      fail(spec, ": gave up after ", max_faults, " faults in a row, ", i, " frames read, nothing written (",
           hal::fault_text(*source), ")");
    frames.rows.push_back(clock.row(grab.header(), i));
    frames.pixels.insert(frames.pixels.end(), grab.pixels().begin(), grab.pixels().end());
  }
  if (frames.rows.empty()) fail(spec, ": delivered no frames, nothing written");
  frames.faults = hal::fault_text(*source);
  frames.skipped = reader.skipped();
  return frames;
}

}  // namespace bolo::cli
