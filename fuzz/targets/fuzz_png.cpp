// PNG frames: scan_png_folder on a folder holding the input as a .png file (and, when the input
// has the separator "\n--bolo-file--\n", the part after it as a second .png), then read_png16.
// Properties: an accepted folder has a non-zero size and each of its files decodes at that size;
// a wrong size or buffer is refused, never written past.

#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "bolo/recording/recording.hpp"
#include "fuzz_support.hpp"

using namespace bolo;

namespace {

// Decoded size bound: PNG headers may declare 2^31 x 2^31 in a few bytes; the caller of
// read_png16 owns the buffer, so this harness declines to allocate beyond 16 MiB.
constexpr std::uint64_t kMaxPixels = 8u << 20;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::array<std::span<const std::uint8_t>, 2> parts;
  const std::size_t n = fuzz::split(std::span(data, size), "\n--bolo-file--\n", parts);
  const std::filesystem::path dir = fuzz::fresh_dir("png");
  for (std::size_t i = 0; i < n; ++i)
    fuzz::write_file(dir / ("frame" + std::to_string(i) + ".png"), parts[i]);

  rec::PngFolder folder;
  try {
    folder = rec::scan_png_folder(dir);
  } catch (const rec::Error&) {
    return 0;
  }
  BOLO_FUZZ_CHECK(folder.files.size() == n);
  BOLO_FUZZ_CHECK(folder.width >= 1 && folder.height >= 1);
  const std::uint64_t pixels = std::uint64_t{folder.width} * folder.height;
  if (pixels > kMaxPixels) return 0;
  // Exactly sized heap buffers so a write past the end is caught.
  std::unique_ptr<std::uint16_t[]> frame(new std::uint16_t[pixels]);
  for (const auto& file : folder.files) {
    try {
      rec::read_png16(file, folder.width, folder.height, std::span(frame.get(), pixels));
    } catch (const rec::Error&) {
      // The header was fine; the image data may still be corrupt.
    }
    // Wrong sizes and buffers: refused before any decoding.
    try {
      rec::read_png16(file, folder.width, folder.height, std::span(frame.get(), pixels - 1));
      BOLO_FUZZ_CHECK(!"a short buffer was accepted");
    } catch (const rec::Error&) {
    }
    if (folder.width > 1) {
      try {
        rec::read_png16(file, folder.width - 1, folder.height,
                        std::span(frame.get(), pixels - folder.height));
        BOLO_FUZZ_CHECK(!"a wrong width was accepted");
      } catch (const rec::Error&) {
      }
    }
  }
  return 0;
}
