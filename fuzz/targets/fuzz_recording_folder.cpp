// A whole recording folder: bolo::rec::Recording validating recording.json, frames.csv,
// frames.npy, camera.json and scene.npy together. The input is split at the separator line
// "\n--bolo-file--\n" into, in order: recording.json, frames.csv, frames.npy, camera.json,
// scene.npy (missing parts: the file is absent; frames.* and recording.json are then refused).
// Properties: an accepted folder agrees with itself (one frames.csv row per frame, frame size
// from recording.json) and every frame, row and scene frame it declares can be read.

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <vector>

#include "bolo/recording/recording.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace bolo;

constexpr std::string_view kSeparator = "\n--bolo-file--\n";
constexpr std::array<const char*, 5> kFiles = {"recording.json", "frames.csv", "frames.npy",
                                               "camera.json", "scene.npy"};

void read_all(rec::Recording& recording) {
  const std::uint64_t n = recording.frame_count();
  BOLO_FUZZ_CHECK(recording.rows().size() == n);
  BOLO_FUZZ_CHECK(recording.width() >= 1 && recording.height() >= 1);
  BOLO_FUZZ_CHECK(!recording.camera() || recording.camera()->is_object());
  if (n == 0) return;
  const std::size_t pixels = std::size_t{recording.width()} * recording.height();
  std::vector<std::uint16_t> frame(pixels), row(recording.width());
  std::vector<float> scene(recording.has_scene() ? pixels : 0);
  for (std::uint64_t i : {std::uint64_t{0}, n / 2, n - 1}) {
    recording.read_frame(i, frame);
    recording.read_row(i, recording.height() - 1, row);
    BOLO_FUZZ_CHECK(std::equal(row.begin(), row.end(), frame.end() - recording.width()));
    if (recording.has_scene()) recording.read_scene(i, scene);
  }
  if (!recording.has_scene()) {
    try {
      recording.read_scene(0, scene);
      BOLO_FUZZ_CHECK(!"read a scene frame from a recording without scene.npy");
    } catch (const rec::Error&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::array<std::span<const std::uint8_t>, kFiles.size()> parts;
  const std::size_t n = fuzz::split(std::span(data, size), kSeparator, parts);
  const std::filesystem::path dir = fuzz::fresh_dir("rec");
  for (std::size_t i = 0; i < n; ++i) fuzz::write_file(dir / kFiles[i], parts[i]);

  std::optional<rec::Recording> recording;
  try {
    recording.emplace(dir);
  } catch (const rec::Error&) {
    return 0;
  }
  try {
    read_all(*recording);
  } catch (const rec::Error& e) {
    std::fprintf(stderr, "accepted recording refused a read: %s\n", e.what());
    BOLO_FUZZ_CHECK(!"an accepted recording refused a read inside it");
  }
  return 0;
}
