#include "bolo/firmware/pipeline.hpp"

namespace bolo::fw {

namespace {

// NUC and bad pixels run as one stage (NUC on the bad-pixel stage's input) when both are enabled
// and both configurations are usable; a misconfigured one keeps its own stage, which passes
// frames through untouched while the other still works.
bool fuse_nuc_into_bad_pixels(const PipelineConfig& config) {
  const std::size_t frame = std::size_t{config.corrector.width} * config.corrector.height;
  return config.use_nuc && config.use_bad_pixels && config.nuc.gain_q14.size() >= frame &&
         config.nuc.offset.size() >= frame &&
         (config.bad_pixels.mask.empty() || config.bad_pixels.mask.size() >= frame);
}

}  // namespace

std::size_t Pipeline::arena_pixels(const PipelineConfig& config) {
  const std::uint32_t w = config.corrector.width;
  const std::uint32_t h = config.corrector.height;
  std::size_t pixels = TwoFrameCorrector::storage_pixels(w, h);
  if (config.use_bad_pixels) pixels += BadPixelStage::storage_pixels(w, h);
  if (config.use_nuc && !fuse_nuc_into_bad_pixels(config)) pixels += NucStage::storage_pixels(w);
  return pixels;
}

Pipeline::Pipeline(const PipelineConfig& config, std::span<Pixel> arena, LineSink& output) {
  const std::uint32_t w = config.corrector.width;
  const std::uint32_t h = config.corrector.height;
  std::span<Pixel> rest = arena;
  auto take = [&rest](std::size_t n) {
    const std::size_t k = n <= rest.size() ? n : rest.size();
    std::span<Pixel> part = rest.subspan(0, k);
    rest = rest.subspan(k);
    return part;
  };
  // Built back to front: each stage needs its successor at construction.
  corrector_.emplace(config.corrector, take(TwoFrameCorrector::storage_pixels(w, h)), output);
  input_ = &*corrector_;
  if (config.use_bad_pixels) {
    BadPixelConfig bad = config.bad_pixels;
    bad.width = w;
    bad.height = h;
    if (fuse_nuc_into_bad_pixels(config)) {
      bad_pixels_.emplace(bad, config.nuc, take(BadPixelStage::storage_pixels(w, h)), *input_);
      input_ = &*bad_pixels_;
      return;
    }
    bad_pixels_.emplace(bad, take(BadPixelStage::storage_pixels(w, h)), *input_);
    input_ = &*bad_pixels_;
  }
  if (config.use_nuc) {
    nuc_.emplace(w, h, config.nuc, take(NucStage::storage_pixels(w)), *input_);
    input_ = &*nuc_;
  }
}

}  // namespace bolo::fw
