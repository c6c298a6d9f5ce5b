#include "nuc_file.hpp"

#include <cmath>
#include <optional>

#include "bolo/recording/recording.hpp"
#include "bolo/correct/fail.hpp"

namespace bolo::correct {

NucFile read_nuc_file(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height) {
  const std::string flag = "--nuc " + file.string();
  std::optional<rec::NpyFrameReader> reader;
  try {
    reader.emplace(file, rec::DType::f4);
  } catch (const rec::Error& e) {
    fail("--nuc ", e.what());
  }
  if (reader->frames() != 2 || reader->height() != height || reader->width() != width)
    fail(flag, ": shape (", reader->frames(), ", ", reader->height(), ", ", reader->width(), "), expected (2, ", height,
         ", ", width, "): each pixel's gain, then its offset, for the source's ", width, "x", height, " frames");
  const std::size_t pixels = std::size_t{width} * height;
  std::vector<float> plane(pixels);
  const auto where = [width](std::size_t p) {
    return "pixel (" + std::to_string(p % width) + ", " + std::to_string(p / width) + ")";
  };
  NucFile nuc;
  nuc.gain_q14.resize(pixels);
  nuc.offset.resize(pixels);
  reader->read_frame(0, plane);
  constexpr double kUnity = fw::kNucUnityGain;
  for (std::size_t p = 0; p < pixels; ++p) {
    const double q14 = std::round(plane[p] * kUnity);
    if (!std::isfinite(plane[p]) || q14 < 0 || q14 > 65535)
      fail(flag, ": gain at ", where(p), ": ", plane[p], " is outside 0 .. ", 65535 / kUnity, " (the firmware's Q2.14)");
    nuc.gain_q14[p] = static_cast<std::uint16_t>(q14);
  }
  reader->read_frame(1, plane);
  for (std::size_t p = 0; p < pixels; ++p) {
    const double counts = std::round(plane[p]);
    if (!std::isfinite(plane[p]) || counts < -32768 || counts > 32767)
      fail(flag, ": offset at ", where(p), ": ", plane[p], " is outside -32768 .. 32767 counts");
    nuc.offset[p] = static_cast<std::int16_t>(counts);
  }
  return nuc;
}

}  // namespace bolo::correct
