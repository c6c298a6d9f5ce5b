#pragma once
// The recording player: a recording in the shared format as a frame source, streamed line by
// line. Host-side (it reads files and throws bolo::rec::Error on bad input).

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::hal {

class RecordingPlayer final : public FrameSource {
 public:
  explicit RecordingPlayer(const std::filesystem::path& dir);
  SourceFormat format() const override { return format_; }
  StreamStatus stream_frame(fw::LineSink& sink) override;
  SourceStats stats() const override { return stats_; }

  std::uint64_t position() const { return next_; }
  void seek(std::uint64_t frame) { next_ = frame; }
  const rec::Recording& recording() const { return recording_; }
  // Every frame's header, as stream_frame delivers it (from frames.csv).
  std::span<const fw::FrameHeader> headers() const { return headers_; }
  // Frame `frame`'s steady-state scene (scene.npy); only when recording().has_scene().
  void read_scene(std::uint64_t frame, std::span<float> out) { recording_.read_scene(frame, out); }

 private:
  rec::Recording recording_;
  SourceFormat format_;
  std::vector<fw::FrameHeader> headers_;
  std::vector<fw::Pixel> line_;
  std::uint64_t next_ = 0;
  SourceStats stats_;
};

}  // namespace bolo::hal
