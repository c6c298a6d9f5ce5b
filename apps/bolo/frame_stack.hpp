#pragma once
// Read access to a recording for the viewing commands (info, render): the shared format with
// uint16 frames.npy (validated by bolo::rec::Recording), or the float32 frames.npy that
// `bolo correct --float` writes (validated here the same way). Frames come out as float.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "bolo/recording/recording.hpp"

namespace bolo::cli {

// Throws bolo::cli::Error naming `dir` when it is not an existing folder.
void require_recording_folder(const std::filesystem::path& dir);

class FrameStack {
 public:
  explicit FrameStack(const std::filesystem::path& dir);

  const std::filesystem::path& dir() const { return dir_; }
  const rec::RecordingInfo& info() const { return info_; }
  const std::vector<rec::FrameRow>& rows() const { return rows_; }
  std::uint64_t frames() const { return rows_.size(); }
  std::uint32_t width() const { return info_.width; }
  std::uint32_t height() const { return info_.height; }
  std::size_t pixels() const { return std::size_t{info_.width} * info_.height; }
  bool is_float() const { return f4_.has_value(); }
  bool has_camera() const { return has_camera_; }

  void read(std::uint64_t index, std::span<float> out);

 private:
  std::filesystem::path dir_;
  rec::RecordingInfo info_;
  std::vector<rec::FrameRow> rows_;
  std::optional<rec::Recording> u2_;
  std::optional<rec::NpyFrameReader> f4_;
  std::vector<std::uint16_t> buffer_;
  bool has_camera_ = false;
};

}  // namespace bolo::cli
