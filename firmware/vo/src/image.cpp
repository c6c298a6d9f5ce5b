#include "bolo/vo/image.hpp"

namespace bolo::vo {

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
  const float* v = lv.value.data;
  for (std::uint32_t y = 0; y < h; ++y) {
    const std::uint32_t ym = y ? y - 1 : 0, yp = y + 1 < h ? y + 1 : y;
    const float* row = v + std::size_t{y} * w;
    const float* up = v + std::size_t{ym} * w;
    const float* down = v + std::size_t{yp} * w;
    float* gx = lv.gx.data + std::size_t{y} * w;
    float* gy = lv.gy.data + std::size_t{y} * w;
    // Central differences, clamped at the borders (the first and last column below).
    for (std::uint32_t x = 0; x < w; ++x) gy[x] = 0.5f * (down[x] - up[x]);
    if (w < 2) {
      if (w == 1) gx[0] = 0.0f;
      continue;
    }
    gx[0] = 0.5f * (row[1] - row[0]);
    for (std::uint32_t x = 1; x + 1 < w; ++x) gx[x] = 0.5f * (row[x + 1] - row[x - 1]);
    gx[w - 1] = 0.5f * (row[w - 1] - row[w - 2]);
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

void smooth_binomial(Image& image, Image& scratch) {
  const std::uint32_t w = image.width, h = image.height;
  if (w == 0 || h == 0) return;
  for (std::uint32_t y = 0; y < h; ++y) {
    const float* in = image.data + std::size_t{y} * w;
    float* out = scratch.data + std::size_t{y} * w;
    if (w == 1) {
      out[0] = in[0];
      continue;
    }
    out[0] = 0.75f * in[0] + 0.25f * in[1];
    for (std::uint32_t x = 1; x + 1 < w; ++x) out[x] = 0.25f * (in[x - 1] + in[x + 1]) + 0.5f * in[x];
    out[w - 1] = 0.25f * in[w - 2] + 0.75f * in[w - 1];
  }
  for (std::uint32_t y = 0; y < h; ++y) {
    const float* up = scratch.data + std::size_t{y ? y - 1 : 0} * w;
    const float* row = scratch.data + std::size_t{y} * w;
    const float* down = scratch.data + std::size_t{y + 1 < h ? y + 1 : y} * w;
    float* out = image.data + std::size_t{y} * w;
    for (std::uint32_t x = 0; x < w; ++x) out[x] = 0.25f * (up[x] + down[x]) + 0.5f * row[x];
  }
}

std::size_t texel_count(std::uint32_t width, std::uint32_t height, std::uint32_t levels) {
  std::size_t total = 0;
  for (std::uint32_t l = 0; l < levels; ++l) total += std::size_t{width >> l} * (height >> l);
  return total;
}

void make_texels(std::span<Texel> storage, std::uint32_t width, std::uint32_t height, std::uint32_t levels,
                 TexelImage* out) {
  std::size_t offset = 0;
  for (std::uint32_t l = 0; l < levels; ++l) {
    const std::uint32_t w = width >> l, h = height >> l;
    out[l] = {storage.data() + offset, w, h};
    offset += std::size_t{w} * h;
  }
}

void fill_texels(const Pyramid& p, TexelImage* texels) {
  for (std::uint32_t l = 0; l < p.levels; ++l) {
    const Level& lv = p.level[l];
    const std::size_t n = std::size_t{lv.value.width} * lv.value.height;
    Texel* t = texels[l].data;
    for (std::size_t i = 0; i < n; ++i) t[i] = {lv.value.data[i], lv.gx.data[i], lv.gy.data[i], 0.0f};
  }
}

}  // namespace bolo::vo
