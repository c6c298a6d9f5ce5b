#include "bolo/frame_stack.hpp"

#include "bolo/hal/source_registry.hpp"

#include "bolo/errors.hpp"

namespace bolo::cli {

namespace fs = std::filesystem;

void require_recording_folder(const fs::path& dir) {
  try {
    hal::require_recording_folder(dir);
  } catch (const hal::SourceError& e) {
    fail(e.what());
  }
}

FrameStack::FrameStack(const fs::path& dir) : dir_(dir) {
  require_recording_folder(dir);
  const fs::path npy = dir / "frames.npy";
  if (!fs::exists(npy)) fail(npy.string(), ": missing (every recording has frames.npy)");
  const rec::NpyHeader header = rec::read_npy_header(npy);
  if (header.dtype == rec::DType::u2) {
    u2_.emplace(dir);
    info_ = u2_->info();
    rows_ = u2_->rows();
    has_camera_ = u2_->camera().has_value();
    buffer_.resize(pixels());
    return;
  }
  // float32 frames (bolo correct --float): the checks Recording does for uint16 files.
  info_ = rec::read_recording_json(dir / "recording.json");
  rows_ = rec::read_frames_csv(dir / "frames.csv");
  f4_.emplace(npy, rec::DType::f4);
  if (f4_->header().shape.size() != 3)
    fail(npy.string(), ": expected shape (N, H, W), got ", f4_->header().shape.size(), " dimensions");
  if (f4_->height() != info_.height || f4_->width() != info_.width)
    fail(npy.string(), ": frames are ", f4_->width(), "x", f4_->height(), " but recording.json says ",
         info_.width, "x", info_.height);
  if (f4_->frames() != rows_.size())
    fail(npy.string(), ": ", f4_->frames(), " frames but frames.csv has ", rows_.size(), " rows");
  has_camera_ = fs::exists(dir / "camera.json");
}

void FrameStack::read(std::uint64_t index, std::span<float> out) {
  if (index >= frames()) fail(dir_.string(), ": frame ", index, ": out of range (", frames(), " frames)");
  if (out.size() != pixels()) throw std::logic_error("FrameStack::read: wrong buffer size");
  if (f4_) {
    f4_->read_frame(index, out);
    return;
  }
  u2_->read_frame(index, buffer_);
  for (std::size_t i = 0; i < buffer_.size(); ++i) out[i] = static_cast<float>(buffer_[i]);
}

}  // namespace bolo::cli
