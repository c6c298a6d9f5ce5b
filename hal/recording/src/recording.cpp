// A whole recording folder, validated on open.

#include <system_error>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {
namespace {

using detail::fail;

const std::filesystem::path& checked_dir(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    fail(dir, std::filesystem::exists(dir, ec) ? "not a folder (a recording is a folder)"
                                               : "no such recording folder");
  if (!std::filesystem::exists(dir / "recording.json", ec))
    fail(dir, "not a recording folder (no recording.json)");
  return dir;
}

}  // namespace

Recording::Recording(const std::filesystem::path& dir)
    : dir_(checked_dir(dir)),
      info_(read_recording_json(dir / "recording.json")),
      rows_(read_frames_csv(dir / "frames.csv")),
      frames_(dir / "frames.npy", DType::u2) {
  const std::filesystem::path npy = dir / "frames.npy";
  if (frames_.height() != info_.height || frames_.width() != info_.width)
    fail(npy, "shape " + detail::shape_string(frames_.header().shape) +
                  " disagrees with recording.json (" + detail::size_string(info_.height, info_.width) +
                  ")");
  if (rows_.size() != frames_.frames())
    fail(dir / "frames.csv", std::to_string(rows_.size()) + " rows but frames.npy has " +
                                 std::to_string(frames_.frames()) + " frames");

  std::error_code ec;
  const std::filesystem::path scene = dir / "scene.npy";
  if (std::filesystem::exists(scene, ec)) {
    scene_.emplace(scene, DType::f4);
    if (scene_->header().shape != frames_.header().shape)
      fail(scene, "shape " + detail::shape_string(scene_->header().shape) +
                      " disagrees with frames.npy " + detail::shape_string(frames_.header().shape));
  }

  const std::filesystem::path camera = dir / "camera.json";
  if (std::filesystem::exists(camera, ec)) {
    nlohmann::json j = detail::parse_json_file(camera);
    if (!j.is_object()) fail(camera, "expected a JSON object");
    camera_ = std::move(j);
  }
}

void Recording::read_scene(std::uint64_t index, std::span<float> out) {
  if (!scene_) fail(dir_ / "scene.npy", "absent (this recording has no scene)");
  scene_->read_frame(index, out);
}

}  // namespace bolo::rec
