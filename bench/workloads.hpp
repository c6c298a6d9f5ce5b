#pragma once
// What bolo-bench times, one frame at a time:
//   MemcpyWorkload     memcpy of a frame-sized buffer (1 read + 1 write): the yardstick
//   CorrectorWorkload  lines pushed through a TwoFrameCorrector, carry-over applied every frame
//   PipelineWorkload   lines pushed through Pipeline: NUC -> bad pixels -> corrector
// All three cycle through the same few input frames, so their input-side cache behaviour is alike.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "bolo/firmware/pipeline.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "harness.hpp"
#include "scene.hpp"

namespace bolo::bench {

// The output end of a stage under test: touches one pixel per line (so the stage's work cannot
// be optimised away) and nothing else.
class TouchSink final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader&) override {}
  void push_line(std::uint32_t row, fw::LineView line) override {
    checksum_ += line[row % line.size()];
    ++lines_;
  }
  // The same pixels, without a call per line: what a sink that takes runs looks like. The
  // column row % width is stepped along the run (one division per call, not one per line: a
  // 64-bit division per 160-pixel line was ~13 % of the corrector's time at 160x120).
  void push_lines(std::uint32_t first_row, std::uint32_t count, const fw::Pixel* pixels,
                  std::size_t width, std::size_t stride) override {
    if (count == 0) return;
    std::size_t column = first_row % width;
    const fw::Pixel* line = pixels;
    for (std::uint32_t i = 0; i < count; ++i, line += stride) {
      checksum_ += line[column];
      column = column + 1 == width ? 0 : column + 1;
    }
    lines_ += count;
  }
  void end_frame() override {}
  std::uint64_t checksum() const { return checksum_; }
  std::uint64_t lines() const { return lines_; }

 private:
  std::uint64_t checksum_ = 0;
  std::uint64_t lines_ = 0;
};

// Plays the input frames in a loop with a clean header chain: consecutive sequence numbers, a
// steady 60 Hz timestamp, exposure and readout times, no FFC.
class FrameFeeder {
 public:
  static constexpr std::uint32_t kExposureNs = 10'000'000;
  static constexpr std::uint32_t kReadoutNs = 6'666'667;
  static constexpr std::uint32_t kPeriodNs = kExposureNs + kReadoutNs;

  explicit FrameFeeder(const BenchData& data) : data_(&data) {}
  void push_frame(fw::LineSink& sink);

 private:
  const BenchData* data_;
  std::uint64_t sequence_ = 0;
};

fw::CorrectorConfig bench_corrector_config(std::uint32_t width, std::uint32_t height);

class MemcpyWorkload final : public Workload {
 public:
  explicit MemcpyWorkload(const BenchData& data);
  void run(std::size_t frames) override;

 private:
  const BenchData* data_;
  std::vector<std::uint16_t> dst_;
  std::size_t next_ = 0;
};

class CorrectorWorkload final : public Workload {
 public:
  explicit CorrectorWorkload(const BenchData& data);
  void run(std::size_t frames) override;
  // Frames (after the warm-up) whose carry-over was not `applied`: must stay 0.
  std::uint64_t not_applied() const { return not_applied_; }
  std::uint64_t checksum() const { return sink_.checksum(); }

 private:
  FrameFeeder feeder_;
  std::vector<fw::Pixel> storage_;
  TouchSink sink_;
  fw::TwoFrameCorrector corrector_;
  std::uint64_t not_applied_ = 0;
};

class PipelineWorkload final : public Workload {
 public:
  explicit PipelineWorkload(const BenchData& data);
  void run(std::size_t frames) override;
  std::uint64_t not_applied() const { return not_applied_; }
  std::uint64_t checksum() const { return sink_.checksum(); }

 private:
  static fw::PipelineConfig config_for(const BenchData& data);

  FrameFeeder feeder_;
  fw::PipelineConfig config_;
  std::vector<fw::Pixel> arena_;
  TouchSink sink_;
  fw::Pipeline pipeline_;
  std::uint64_t not_applied_ = 0;
};

}  // namespace bolo::bench
