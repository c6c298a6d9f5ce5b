#include "bolo/vo/image.hpp"

namespace bolo::vo {

float bilinear(const Image& img, float x, float y) {
  const auto xi = static_cast<std::uint32_t>(x), yi = static_cast<std::uint32_t>(y);
  const float fx = x - static_cast<float>(xi), fy = y - static_cast<float>(yi);
  const float* p = img.data + std::size_t{yi} * img.width + xi;
  const float top = p[0] + fx * (p[1] - p[0]);
  const float bottom = p[img.width] + fx * (p[img.width + 1] - p[img.width]);
  return top + fy * (bottom - top);
}

Sample bilinear_with_gradient(const Image& img, const Image& gx, const Image& gy, float x, float y) {
  // bilinear() on the three planes with the weights and offsets computed once (same arithmetic,
  // same results).
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

std::size_t pyramid_floats(std::uint32_t width, std::uint32_t height, std::uint32_t levels) {
  std::size_t total = 0;
  for (std::uint32_t l = 0; l < levels; ++l) total += 3 * std::size_t{width >> l} * (height >> l);
  return total;
}

Pyramid make_pyramid(std::span<float> storage, std::uint32_t width, std::uint32_t height,
                     std::uint32_t levels) {
  Pyramid p;
  p.levels = levels;
  std::size_t offset = 0;
  for (std::uint32_t l = 0; l < levels; ++l) {
    const std::uint32_t w = width >> l, h = height >> l;
    const std::size_t n = std::size_t{w} * h;
    p.level[l].value = {storage.data() + offset, w, h};
    p.level[l].gx = {storage.data() + offset + n, w, h};
    p.level[l].gy = {storage.data() + offset + 2 * n, w, h};
    offset += 3 * n;
  }
  return p;
}

static void gradients(Level& lv) {
  const std::uint32_t w = lv.value.width, h = lv.value.height;
  for (std::uint32_t y = 0; y < h; ++y) {
    const std::uint32_t ym = y ? y - 1 : 0, yp = y + 1 < h ? y + 1 : y;
    for (std::uint32_t x = 0; x < w; ++x) {
      const std::uint32_t xm = x ? x - 1 : 0, xp = x + 1 < w ? x + 1 : x;
      const std::size_t i = std::size_t{y} * w + x;
      lv.gx.data[i] = 0.5f * (lv.value.at(xp, y) - lv.value.at(xm, y));
      lv.gy.data[i] = 0.5f * (lv.value.at(x, yp) - lv.value.at(x, ym));
    }
  }
}

void build_pyramid(Pyramid& p) {
  for (std::uint32_t l = 1; l < p.levels; ++l) {
    const Image& src = p.level[l - 1].value;
    Image& dst = p.level[l].value;
    for (std::uint32_t y = 0; y < dst.height; ++y)
      for (std::uint32_t x = 0; x < dst.width; ++x)
        dst.data[std::size_t{y} * dst.width + x] =
            0.25f * (src.at(2 * x, 2 * y) + src.at(2 * x + 1, 2 * y) + src.at(2 * x, 2 * y + 1) +
                     src.at(2 * x + 1, 2 * y + 1));
  }
  for (std::uint32_t l = 0; l < p.levels; ++l) gradients(p.level[l]);
}

}  // namespace bolo::vo
