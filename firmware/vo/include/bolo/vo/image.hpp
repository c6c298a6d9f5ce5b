#pragma once
// Float images for the VO: a view over caller storage, bilinear sampling with gradients, and the
// pyramid (each level halves the size by 2x2 averaging; gradients by central differences).

#include <cstdint>
#include <span>

namespace bolo::vo {

struct Image {
  float* data = nullptr;
  std::uint32_t width = 0, height = 0;
  float at(std::uint32_t x, std::uint32_t y) const { return data[std::size_t{y} * width + x]; }
};

// Value and gradient at a sub-pixel position.
struct Sample {
  float value = 0, gx = 0, gy = 0;
};

// True when (x, y) is at least `margin` pixels inside the image.
inline bool inside(const Image& img, float x, float y, float margin) {
  return x >= margin && y >= margin && x <= static_cast<float>(img.width) - 1.0f - margin &&
         y <= static_cast<float>(img.height) - 1.0f - margin;
}

// Bilinear value; the caller keeps (x, y) inside with a margin of at least 1.
float bilinear(const Image& img, float x, float y);
// Bilinear value and gradient (from the gradient images gx, gy of the same size).
Sample bilinear_with_gradient(const Image& img, const Image& gx, const Image& gy, float x, float y);

// Per level: intensity, x gradient, y gradient.
struct Level {
  Image value, gx, gy;
};

struct Pyramid {
  Level level[8];
  std::uint32_t levels = 0;
};

// Floats a pyramid of `levels` levels of a width x height image needs (3 planes per level).
std::size_t pyramid_floats(std::uint32_t width, std::uint32_t height, std::uint32_t levels);
// Lays a pyramid out over `storage` (pyramid_floats long).
Pyramid make_pyramid(std::span<float> storage, std::uint32_t width, std::uint32_t height,
                     std::uint32_t levels);
// Fill level 0's value plane first, then call this: downsamples and computes all gradients.
void build_pyramid(Pyramid& pyramid);

}  // namespace bolo::vo
