#include "bolo/hal/png_folder_source.hpp"

#include <cmath>
#include <string>

namespace bolo::hal {

PngFolderSource::PngFolderSource(const std::filesystem::path& dir, double fps)
    : folder_(rec::scan_png_folder(dir)) {
  if (!(fps > 0) || !std::isfinite(fps))
    throw rec::Error(dir.string() + ": frame rate must be a positive number, got " +
                     std::to_string(fps));
  format_.width = folder_.width;
  format_.height = folder_.height;
  format_.bits = 16;
  format_.frame_period_ns = static_cast<std::uint32_t>(std::lround(1e9 / fps));
  frame_.resize(std::size_t{folder_.width} * folder_.height);
}

StreamStatus PngFolderSource::stream_frame(fw::LineSink& sink) {
  if (next_ >= folder_.files.size()) return StreamStatus::end_of_stream;
  const std::uint64_t index = next_++;
  rec::read_png16(folder_.files[index], folder_.width, folder_.height, frame_);
  fw::FrameHeader header;
  header.width = folder_.width;
  header.height = folder_.height;
  header.sequence = index;
  header.sequence_valid = true;
  header.timestamp_ns = static_cast<std::int64_t>(index) * format_.frame_period_ns;
  header.timestamp_valid = true;
  sink.begin_frame(header);
  sink.push_lines(0, folder_.height, frame_.data(), folder_.width, folder_.width);  // the whole frame is here
  sink.end_frame();
  ++stats_.frames_delivered;
  return StreamStatus::frame;
}

}  // namespace bolo::hal
