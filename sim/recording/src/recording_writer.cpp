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

bool exists_no_follow(const fs::path& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}

// Something `overwrite` may replace: a recording folder or an empty folder, never anything else.
void check_replaceable(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec)))
    fail(dir, "exists and is not a folder; refusing to replace it");
  if (!fs::exists(dir / "recording.json", ec) && !fs::is_empty(dir, ec))
    fail(dir, "exists and is not a recording folder (no recording.json); refusing to replace it");
}

// Checks the destination before any work, then creates the temporary folder.
fs::path prepare(const fs::path& dir, const RecordingInfo& info, bool overwrite) {
  if (dir.empty() || dir.filename() == "." || dir.filename() == "..")
    throw Error("recording folder '" + dir.string() + "': not a valid destination name");
  if (exists_no_follow(dir)) {
    if (!overwrite) fail(dir, "already exists (use --overwrite to replace it)");
    check_replaceable(dir);
  }
  const fs::path parent = dir.parent_path().empty() ? fs::path(".") : dir.parent_path();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    fail(dir, "the parent folder " + parent.string() + " does not exist");
  detail::validate_info(dir / "recording.json", info);

  const fs::path tmp = detail::temp_sibling(dir, "tmp");
  if (!fs::create_directory(tmp, ec) || ec)
    fail(tmp, "cannot create the temporary folder: " + (ec ? ec.message() : "it already exists"));
  return tmp;
}

NpyStackWriter open_stack(const fs::path& tmp, DType dtype, std::uint32_t height, std::uint32_t width) {
  try {
    return NpyStackWriter(tmp / "frames.npy", dtype, height, width);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
}

bool reserved(const fs::path& relative) {
  return relative == "recording.json" || relative == "frames.npy" || relative == "frames.csv" ||
         relative == "camera.json";
}

}  // namespace

RecordingWriter::RecordingWriter(fs::path dir, RecordingInfo info, Options options)
    : dir_(normalized(std::move(dir))),
      tmp_(prepare(dir_, info, options.overwrite)),
      info_(std::move(info)),
      options_(options),
      frames_(open_stack(tmp_, options.frames_dtype, info_.height, info_.width)) {}

RecordingWriter::~RecordingWriter() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(tmp_, ec);
}

namespace {

// Checks one frame and its row before anything is written; returns the row as it will be stored.
FrameRow checked_row(const fs::path& dir, const RecordingInfo& info, const std::vector<FrameRow>& rows,
                     std::size_t pixels, const FrameRow& row, bool committed) {
  if (committed) fail(dir, "append after commit()");
  const std::uint64_t n = rows.size();
  const std::uint64_t expected = std::uint64_t{info.width} * info.height;
  if (pixels != expected)
    detail::fail_frame(dir / "frames.npy", n, {},
                       std::to_string(pixels) + " pixels, expected " + std::to_string(expected) +
                           " (" + detail::size_string(info.height, info.width) + ")");
  FrameRow stored = row;
  stored.index = n;  // frames.csv's index is the row number
  detail::RowValidator validator(dir / "frames.csv");
  for (auto it = rows.rbegin(); it != rows.rend(); ++it)
    if (it->t_s) {
      validator.seed(*it->t_s);
      break;
    }
  validator.check(stored, n);
  return stored;
}

}  // namespace

void RecordingWriter::append(std::span<const std::uint16_t> frame, const FrameRow& row) {
  const FrameRow stored = checked_row(dir_, info_, rows_, frame.size(), row, committed_);
  frames_.append(frame);
  rows_.push_back(stored);
}

void RecordingWriter::append(std::span<const float> frame, const FrameRow& row) {
  const FrameRow stored = checked_row(dir_, info_, rows_, frame.size(), row, committed_);
  if (options_.frames_dtype != DType::f4)
    fail(dir_ / "frames.npy", "float frames need Options::frames_dtype = DType::f4");
  frames_.append(frame);
  rows_.push_back(stored);
}

void RecordingWriter::append_scene(std::span<const float> scene) {
  if (committed_) fail(dir_, "append_scene after commit()");
  const std::uint64_t expected = std::uint64_t{info_.width} * info_.height;
  const std::uint64_t n = scene_ ? scene_->frames() : 0;
  if (scene.size() != expected)
    detail::fail_frame(dir_ / "scene.npy", n, {},
                       std::to_string(scene.size()) + " pixels, expected " + std::to_string(expected));
  if (!scene_) {
    for (const auto& [existing, unused] : extra_files_)
      if (existing == "scene.npy") fail(dir_ / "scene.npy", "already added as an extra file");
    scene_.emplace(tmp_ / "scene.npy", DType::f4, info_.height, info_.width);
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
  if (committed_) fail(dir_, "commit() called twice");
  frames_.finish();
  if (scene_) {
    if (scene_->frames() != rows_.size())
      fail(dir_ / "scene.npy", std::to_string(scene_->frames()) + " scene frames for " +
                                   std::to_string(rows_.size()) + " frames");
    scene_->finish();
  }
  write_frames_csv(tmp_ / "frames.csv", rows_);
  write_recording_json(tmp_ / "recording.json", info_);
  if (camera_) write_file_atomically(tmp_ / "camera.json", camera_->dump(2) + "\n");
  for (const auto& [relative, contents] : extra_files_) {
    const fs::path file = tmp_ / relative;
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    if (ec) fail(file.parent_path(), "cannot create folder: " + ec.message());
    write_file_atomically(file, contents);
  }

  std::error_code ec;
  if (exists_no_follow(dir_)) {
    if (!options_.overwrite) fail(dir_, "appeared while writing (use --overwrite to replace it)");
    check_replaceable(dir_);
    const fs::path aside = detail::temp_sibling(dir_, "old");
    fs::rename(dir_, aside, ec);
    if (ec) fail(dir_, "cannot move the existing recording aside: " + ec.message());
    fs::rename(tmp_, dir_, ec);
    if (ec) {
      std::error_code ignored;
      fs::rename(aside, dir_, ignored);
      fail(dir_, "cannot rename the new recording into place: " + ec.message());
    }
    committed_ = true;
    fs::remove_all(aside, ec);
    if (ec) fail(aside, "the new recording is in place but the old one could not be removed: " + ec.message());
    return;
  }
  fs::rename(tmp_, dir_, ec);
  if (ec) fail(dir_, "cannot rename the new recording into place: " + ec.message());
  committed_ = true;
}

}  // namespace bolo::rec
