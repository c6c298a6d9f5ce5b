// .npy reader: read_npy_header and NpyFrameReader (uint16 and float32) on the input as a file.
// Properties: a header that is accepted declares no more data than the file holds, and then
// every frame and row it declares can be read (a refusal there is a finding).

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <vector>

#include "bolo/recording/recording.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace bolo;

constexpr std::uint64_t kMaxFramesRead = 16;  // first frames, plus the last one

void read_stack(rec::NpyFrameReader& reader, rec::DType dtype, std::uint64_t file_size) {
  const rec::NpyHeader& h = reader.header();
  BOLO_FUZZ_CHECK(h.shape.size() == 3);
  BOLO_FUZZ_CHECK(h.data_offset <= file_size);
  const std::uint64_t n = reader.frames(), height = reader.height(), width = reader.width();
  if (n == 0) return;
  // Accepted, so N*H*W items fit in the file: the pixel count of one frame is small.
  const std::uint64_t item = dtype == rec::DType::u2 ? 2 : 4;
  BOLO_FUZZ_CHECK(height * width <= (file_size - h.data_offset) / item / n);
  const std::size_t pixels = static_cast<std::size_t>(height * width);
  std::vector<std::uint64_t> frames;
  for (std::uint64_t i = 0; i < std::min(n, kMaxFramesRead); ++i) frames.push_back(i);
  frames.push_back(n - 1);
  if (dtype == rec::DType::u2) {
    std::vector<std::uint16_t> frame(pixels), row(static_cast<std::size_t>(width));
    for (std::uint64_t i : frames) {
      reader.read_frame(i, frame);
      for (std::uint64_t r = 0; r < std::min<std::uint64_t>(height, 64); ++r) {
        reader.read_row(i, r, row);
        BOLO_FUZZ_CHECK(std::equal(row.begin(), row.end(), frame.begin() + static_cast<std::ptrdiff_t>(r * width)));
      }
    }
    // Requests outside the stack are refusals, not reads.
    try {
      reader.read_frame(n, frame);
      BOLO_FUZZ_CHECK(!"frame index past the end was read");
    } catch (const rec::Error&) {
    }
    if (height > 0) {
      try {
        reader.read_row(0, height, row);
        BOLO_FUZZ_CHECK(!"row past the end was read");
      } catch (const rec::Error&) {
      }
    }
  } else {
    std::vector<float> frame(pixels);
    for (std::uint64_t i : frames) reader.read_frame(i, frame);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path file = fuzz::scratch_dir() / "frames.npy";
  fuzz::write_file(file, std::span(data, size));
  try {
    const rec::NpyHeader h = rec::read_npy_header(file);
    BOLO_FUZZ_CHECK(h.data_offset <= size);
    std::uint64_t bytes = h.dtype == rec::DType::u2 ? 2 : 4;
    for (std::uint64_t d : h.shape) {
      BOLO_FUZZ_CHECK(d == 0 || bytes <= UINT64_MAX / d);
      bytes *= d;
    }
    BOLO_FUZZ_CHECK(bytes <= size - h.data_offset);
  } catch (const rec::Error&) {
  }
  for (rec::DType dtype : {rec::DType::u2, rec::DType::f4}) {
    std::optional<rec::NpyFrameReader> reader;
    try {
      reader.emplace(file, dtype);
    } catch (const rec::Error&) {
      continue;  // refused: fine
    }
    try {
      read_stack(*reader, dtype, size);
    } catch (const rec::Error& e) {
      std::fprintf(stderr, "refused a read of an accepted stack: %s\n", e.what());
      BOLO_FUZZ_CHECK(!"an accepted .npy stack refused a read inside it");
    }
  }
  return 0;
}
