// RecordingWriter: write into a temporary sibling folder, rename into place on commit().

#include <system_error>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {
namespace {

using detail::fail;
namespace fs = std::filesystem;

fs::path normalized(fs::path dir) {
  if (!dir.empty() && !dir.has_filename()) dir = dir.parent_path();  // "out/rec/" -> "out/rec"
  return dir;
}

// Something `overwrite` may replace: a recording folder or an empty folder, never anything else.
void check_replaceable(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec)))
    fail(dir, "exists and is not a folder; refusing to replace it");
  if (!fs::exists(dir / "recording.json", ec) && !fs::is_empty(dir, ec))
    fail(dir, "exists and is not a recording folder (no recording.json); refusing to replace it");
}

// The temporary folder of a recording, after its metadata is checked; only a recording or an
// empty folder may be replaced.
AtomicFolder open_folder(const fs::path& dir, const RecordingInfo& info, bool overwrite) {
  detail::validate_info(dir / "recording.json", info);
  return AtomicFolder(dir, overwrite, check_replaceable);
}


bool reserved(const fs::path& relative) {
  return relative == "recording.json" || relative == "frames.npy" || relative == "frames.csv" ||
         relative == "camera.json";
}

}  // namespace

RecordingWriter::RecordingWriter(fs::path dir, RecordingInfo info, Options options)
    : dir_(normalized(std::move(dir))),
      folder_(open_folder(dir_, info, options.overwrite)),
      info_(std::move(info)),
      options_(options),
      frames_(folder_.path() / "frames.npy", options.frames_dtype, info_.height, info_.width),
      rows_(folder_.path() / "frames.csv", dir_ / "frames.csv") {}

RecordingWriter::~RecordingWriter() = default;

namespace {

// Checks one frame and its row before anything is written; returns the row as it will be stored.
FrameRow checked_row(const fs::path& dir, const RecordingInfo& info, const FramesCsvWriter& rows,
                     std::size_t pixels, const FrameRow& row, bool committed) {
  if (committed) fail(dir, "append after commit()");
  const std::uint64_t n = rows.rows();
  const std::uint64_t expected = std::uint64_t{info.width} * info.height;
  if (pixels != expected)
    detail::fail_frame(dir / "frames.npy", n, {},
                       std::to_string(pixels) + " pixels, expected " + std::to_string(expected) +
                           " (" + detail::size_string(info.height, info.width) + ")");
  FrameRow stored = row;
  stored.index = n;  // frames.csv's index is the row number
  rows.check(stored);
  return stored;
}

}  // namespace

void RecordingWriter::append(std::span<const std::uint16_t> frame, const FrameRow& row) {
  const FrameRow stored = checked_row(dir_, info_, rows_, frame.size(), row, folder_.committed());
  frames_.append(frame);
  rows_.append(stored);
}

void RecordingWriter::append(std::span<const float> frame, const FrameRow& row) {
  const FrameRow stored = checked_row(dir_, info_, rows_, frame.size(), row, folder_.committed());
  if (options_.frames_dtype != DType::f4)
    fail(dir_ / "frames.npy", "float frames need Options::frames_dtype = DType::f4");
  frames_.append(frame);
  rows_.append(stored);
}

void RecordingWriter::append_scene(std::span<const float> scene) {
  if (folder_.committed()) fail(dir_, "append_scene after commit()");
  const std::uint64_t expected = std::uint64_t{info_.width} * info_.height;
  const std::uint64_t n = scene_ ? scene_->frames() : 0;
  if (scene.size() != expected)
    detail::fail_frame(dir_ / "scene.npy", n, {},
                       std::to_string(scene.size()) + " pixels, expected " + std::to_string(expected));
  if (!scene_) {
    for (const auto& [existing, unused] : extra_files_)
      if (existing == "scene.npy") fail(dir_ / "scene.npy", "already added as an extra file");
    scene_.emplace(folder_.path() / "scene.npy", DType::f4, info_.height, info_.width);
  }
  scene_->append(scene);
}

void RecordingWriter::set_camera(const nlohmann::json& camera) {
  if (!camera.is_object()) fail(dir_ / "camera.json", "expected a JSON object");
  camera_ = camera;
}

void RecordingWriter::add_file(const fs::path& relative, std::string contents) {
  const fs::path clean = relative.lexically_normal();
  bool escapes = relative.empty() || !relative.is_relative() || !clean.has_filename();
  for (const fs::path& part : clean)
    if (part == ".." || part == ".") escapes = true;
  if (escapes) fail(dir_ / relative, "extra files must have a relative path inside the recording");
  if (reserved(clean))
    fail(dir_ / relative, "is written by RecordingWriter itself; cannot be added as an extra file");
  for (const auto& [existing, unused] : extra_files_)
    if (existing == clean) fail(dir_ / relative, "added twice");
  if (scene_ && clean == "scene.npy") fail(dir_ / relative, "written by append_scene already");
  extra_files_.emplace_back(clean, std::move(contents));
}

void RecordingWriter::commit() {
  if (folder_.committed()) fail(dir_, "commit() called twice");
  frames_.finish();
  if (scene_) {
    if (scene_->frames() != rows_.rows())
      fail(dir_ / "scene.npy", std::to_string(scene_->frames()) + " scene frames for " +
                                   std::to_string(rows_.rows()) + " frames");
    scene_->finish();
  }
  rows_.finish();
  write_recording_json(folder_.path() / "recording.json", info_);
  if (camera_) write_file_atomically(folder_.path() / "camera.json", camera_->dump(2) + "\n");
  for (const auto& [relative, contents] : extra_files_) {
    const fs::path file = folder_.path() / relative;
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    if (ec) fail(file.parent_path(), "cannot create folder: " + ec.message());
    write_file_atomically(file, contents);
  }

  folder_.commit();
}

}  // namespace bolo::rec
