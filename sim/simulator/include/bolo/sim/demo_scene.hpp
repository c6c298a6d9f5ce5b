#pragma once
// A small procedural thermal scene for demos and tests: a warm background with a smooth
// gradient, vertical cool bars, and a hot disc crossing the view — sharp moving edges are where
// ghosting shows. Values are steady-state counts.

#include <cstdint>
#include <span>

namespace bolo::sim {

struct DemoSceneOptions {
  double background = 6000.0;   // counts
  double gradient = 800.0;      // counts across the width
  double bar_contrast = -600.0;
  double hot_contrast = 4000.0;
  double speed_px_per_s = 60.0;
};

void render_demo_scene(std::uint32_t width, std::uint32_t height, double t_s,
                       const DemoSceneOptions& options, std::span<float> out);

}  // namespace bolo::sim
