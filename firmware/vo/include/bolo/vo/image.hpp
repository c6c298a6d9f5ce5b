#pragma once
// Float images for the VO: a view over caller storage, bilinear sampling with gradients, and the
// pyramid (each level halves the size by 2x2 averaging; gradients by central differences).

#include <cstdint>
#include <span>

#include <Eigen/Core>

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
inline float bilinear(const Image& img, float x, float y) {
  const auto xi = static_cast<std::uint32_t>(x), yi = static_cast<std::uint32_t>(y);
  const float fx = x - static_cast<float>(xi), fy = y - static_cast<float>(yi);
  const float* p = img.data + std::size_t{yi} * img.width + xi;
  const float top = p[0] + fx * (p[1] - p[0]);
  const float bottom = p[img.width] + fx * (p[img.width + 1] - p[img.width]);
  return top + fy * (bottom - top);
}

// Keys' cubic convolution (a = -1/2): the weights of the four pixels floor(x) - 1 .. floor(x) + 2
// along one axis. Its error on a smooth image is third order in the pixel size where bilinear's
// is second; the tau estimator samples with it (tau_estimator.cpp says why).
struct CubicTaps {
  std::int32_t first = 0;
  float w[4] = {};
};
inline CubicTaps cubic_taps(float x) {
  const auto f = static_cast<std::int32_t>(x);  // x >= 0
  const float t = x - static_cast<float>(f);
  const float t2 = t * t, t3 = t2 * t;
  return {f - 1,
          {-0.5f * t3 + t2 - 0.5f * t, 1.5f * t3 - 2.5f * t2 + 1.0f, -1.5f * t3 + 2.0f * t2 + 0.5f * t,
           0.5f * t3 - 0.5f * t2}};
}
// The caller keeps the taps inside the image (a margin of at least 2 around the position).
inline float cubic(const Image& img, const CubicTaps& tx, const CubicTaps& ty) {
  float sum = 0;
  for (int j = 0; j < 4; ++j) {
    const float* row = img.data + static_cast<std::size_t>(ty.first + j) * img.width + tx.first;
    sum += ty.w[j] * (tx.w[0] * row[0] + tx.w[1] * row[1] + tx.w[2] * row[2] + tx.w[3] * row[3]);
  }
  return sum;
}

// Bilinear value and gradient (from the gradient images gx, gy of the same size): bilinear() on
// the three planes with the weights and offsets computed once (same arithmetic, same results).
inline Sample bilinear_with_gradient(const Image& img, const Image& gx, const Image& gy, float x, float y) {
  const auto xi = static_cast<std::uint32_t>(x), yi = static_cast<std::uint32_t>(y);
  const float fx = x - static_cast<float>(xi), fy = y - static_cast<float>(yi);
  const std::size_t o = std::size_t{yi} * img.width + xi, w = img.width;
  const auto at = [&](const float* p) {
    const float top = p[o] + fx * (p[o + 1] - p[o]);
    const float bottom = p[o + w] + fx * (p[o + w + 1] - p[o + w]);
    return top + fy * (bottom - top);
  };
  return {at(img.data), at(gx.data), at(gy.data)};
}

// One level's value and gradients interleaved per pixel: a bilinear sample of all three reads
// two adjacent 32-byte pairs instead of six scattered ones (the tracker samples the current frame
// this way; the pad keeps a texel 16 bytes).
struct alignas(16) Texel {
  float value, gx, gy, pad;
};
struct TexelImage {
  Texel* data = nullptr;
  std::uint32_t width = 0, height = 0;
};

// bilinear_with_gradient() on the interleaved texels, the three channels at once (one 4-float
// vector a texel; SSE on x86-64, NEON on the boards): per channel the same arithmetic, the same
// results. The texels are 16-byte aligned (the arena's alignment, 16-byte texels).
inline Sample bilinear_with_gradient(const TexelImage& img, float x, float y) {
  const auto xi = static_cast<std::uint32_t>(x), yi = static_cast<std::uint32_t>(y);
  const float fx = x - static_cast<float>(xi), fy = y - static_cast<float>(yi);
  const Texel* p = img.data + std::size_t{yi} * img.width + xi;
  const Texel* q = p + img.width;
  using V = Eigen::Map<const Eigen::Array4f, Eigen::Aligned16>;
  const Eigen::Array4f a = V(&p[0].value), b = V(&p[1].value), c = V(&q[0].value), d = V(&q[1].value);
  const Eigen::Array4f top = a + fx * (b - a);
  const Eigen::Array4f bottom = c + fx * (d - c);
  const Eigen::Array4f r = top + fy * (bottom - top);
  return {r[0], r[1], r[2]};
}

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

// One pass of the 3x3 binomial low-pass ([1 2 1] / 4 along each axis, borders replicated) over
// `image` in place; `scratch` is an image of the same size whose contents it overwrites (before
// build_pyramid, level 0's gradient plane). The VO runs it on each tracking image (why: config.hpp,
// VoConfig::smoothing).
void smooth_binomial(Image& image, Image& scratch);

// Texels of every level of a pyramid (`levels` images over `storage`, texel_count long).
std::size_t texel_count(std::uint32_t width, std::uint32_t height, std::uint32_t levels);
void make_texels(std::span<Texel> storage, std::uint32_t width, std::uint32_t height, std::uint32_t levels,
                 TexelImage* out);
// Interleaves a built pyramid's planes into its texel images.
void fill_texels(const Pyramid& pyramid, TexelImage* texels);

}  // namespace bolo::vo
