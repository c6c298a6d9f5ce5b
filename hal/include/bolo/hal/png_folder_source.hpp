#pragma once
// A folder of 16-bit PNG frames as a frame source; times from a given frame rate.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::hal {

class PngFolderSource final : public FrameSource {
 public:
  PngFolderSource(const std::filesystem::path& dir, double fps);
  SourceFormat format() const override { return format_; }
  StreamStatus stream_frame(fw::LineSink& sink) override;
  SourceStats stats() const override { return stats_; }
  std::uint64_t frame_count() const { return folder_.files.size(); }

 private:
  rec::PngFolder folder_;
  SourceFormat format_;
  std::vector<fw::Pixel> frame_;
  std::uint64_t next_ = 0;
  SourceStats stats_;
};

}  // namespace bolo::hal
