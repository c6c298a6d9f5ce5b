// Corrects one 4x2 frame through the installed library and checks the result.
#include <cstdio>
#include <vector>

#include "bolo/firmware/pipeline.hpp"
#include "bolo/sim/corrector_reference.hpp"

namespace {
class Last final : public bolo::fw::LineSink {
 public:
  void begin_frame(const bolo::fw::FrameHeader&) override {}
  void push_line(std::uint32_t, bolo::fw::LineView line) override { value = line[0]; }
  void end_frame() override {}
  bolo::fw::Pixel value = 0;
};
}  // namespace

int main() {
  bolo::fw::PipelineConfig cfg;
  cfg.corrector.width = 4;
  cfg.corrector.height = 2;
  cfg.corrector.tau = {12'000'000, 12'000'000};
  std::vector<bolo::fw::Pixel> arena(bolo::fw::Pipeline::arena_pixels(cfg));
  Last sink;
  bolo::fw::Pipeline pipeline(cfg, arena, sink);
  bolo::fw::FrameHeader hd;
  hd.width = 4;
  hd.height = 2;
  hd.exposure_ns = 10'000'000;
  std::vector<bolo::fw::Pixel> line(4, 1000);
  pipeline.input().begin_frame(hd);
  pipeline.input().push_line(0, line);
  pipeline.input().push_line(1, line);
  pipeline.input().end_frame();
  std::vector<double> ref(4);
  bolo::sim::correct_frame_reference(line, {}, 0.012, 0.012, 0.01, 0.0, ref);
  std::printf("fixed %u, float %.3f\n", sink.value, ref[0]);
  return (sink.value > ref[0] - 1 && sink.value < ref[0] + 1) ? 0 : 1;
}
