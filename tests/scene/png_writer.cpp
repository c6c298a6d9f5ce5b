#include "png_writer.hpp"

#include <png.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace bolo::test {
namespace {

std::array<unsigned char, 3> ironbow(float x) {
  struct Stop {
    float x;
    float r, g, b;
  };
  static constexpr Stop stops[] = {{0.00f, 0, 0, 0},      {0.15f, 30, 0, 90},     {0.35f, 130, 0, 150},
                                   {0.55f, 210, 50, 60},  {0.75f, 250, 140, 0},   {0.90f, 255, 220, 60},
                                   {1.00f, 255, 255, 255}};
  x = std::clamp(x, 0.0f, 1.0f);
  for (std::size_t i = 1; i < std::size(stops); ++i) {
    if (x <= stops[i].x) {
      const Stop& a = stops[i - 1];
      const Stop& b = stops[i];
      const float f = (x - a.x) / (b.x - a.x);
      return {static_cast<unsigned char>(a.r + f * (b.r - a.r)), static_cast<unsigned char>(a.g + f * (b.g - a.g)),
              static_cast<unsigned char>(a.b + f * (b.b - a.b))};
    }
  }
  return {255, 255, 255};
}

}  // namespace

void write_temperature_png(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                           std::span<const float> kelvin, float lo_k, float hi_k) {
  if (kelvin.size() != static_cast<std::size_t>(width) * height) throw std::invalid_argument("png: size mismatch");
  std::vector<unsigned char> rgb(kelvin.size() * 3);
  for (std::size_t i = 0; i < kelvin.size(); ++i) {
    const auto c = ironbow((kelvin[i] - lo_k) / (hi_k - lo_k));
    std::copy(c.begin(), c.end(), rgb.begin() + static_cast<std::ptrdiff_t>(3 * i));
  }
  FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) throw std::runtime_error("png: cannot open " + file.string());
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    throw std::runtime_error("png: libpng error writing " + file.string());
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (std::uint32_t y = 0; y < height; ++y) png_write_row(png, rgb.data() + static_cast<std::size_t>(y) * width * 3);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

}  // namespace bolo::test
