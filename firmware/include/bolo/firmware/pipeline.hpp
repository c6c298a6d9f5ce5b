#pragma once
// The board's correction chain, built once from a configuration and one caller-provided arena:
//   source -> [NUC] -> [bad pixels] -> two-frame corrector -> output sink
// No allocation: every buffer is carved from the arena at construction.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "bolo/firmware/bad_pixel_stage.hpp"
#include "bolo/firmware/nuc_stage.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"

namespace bolo::fw {

struct PipelineConfig {
  CorrectorConfig corrector;  // its width/height are the frame size
  bool use_nuc = false;
  NucTables nuc;
  bool use_bad_pixels = false;
  BadPixelConfig bad_pixels;  // width/height are taken from the corrector
};

class Pipeline {
 public:
  static std::size_t arena_pixels(const PipelineConfig& config);
  // `arena` must hold arena_pixels(config) pixels and outlive the pipeline.
  Pipeline(const PipelineConfig& config, std::span<Pixel> arena, LineSink& output);
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Where a source pushes its lines.
  LineSink& input() { return *input_; }
  TwoFrameCorrector& corrector() { return *corrector_; }
  const BadPixelStage* bad_pixels() const { return bad_pixels_ ? &*bad_pixels_ : nullptr; }

 private:
  std::optional<TwoFrameCorrector> corrector_;
  std::optional<BadPixelStage> bad_pixels_;
  std::optional<NucStage> nuc_;
  LineSink* input_ = nullptr;
};

}  // namespace bolo::fw
