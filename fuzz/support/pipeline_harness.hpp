#pragma once
// The firmware pipeline as the fuzz targets build it: configuration drawn from the input (size,
// time constants, NUC tables, bad-pixel mask, a deliberately short arena now and then), every
// buffer an exactly sized heap block so ASan sees any access past it, and an output sink that
// reads every pixel it is given and counts lines per frame.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "bolo/firmware/pipeline.hpp"
#include "fuzz_support.hpp"

namespace bolo::fuzz {

// Counts what reaches the end of the chain and touches every pixel (so a view into freed or
// foreign memory is caught). Properties: a line is never longer than `max_width`, and from a
// begin_frame or end_frame to the next end_frame as many lines come out as went in. `lines_in`
// belongs to the caller, which pushes into the pipeline: it counts its pushes and sets it to 0
// after each begin_frame / end_frame call returns.
class CheckingSink final : public fw::LineSink {
 public:
  explicit CheckingSink(std::size_t max_width) : max_width_(max_width) {}
  void begin_frame(const fw::FrameHeader&) override {
    ++frames_begun;
    lines_out = 0;
  }
  void push_line(std::uint32_t, fw::LineView line) override {
    BOLO_FUZZ_CHECK(line.size() <= max_width_);
    std::uint32_t sum = 0;
    for (fw::Pixel p : line) sum += p;
    checksum += sum;
    ++lines_out;
    ++total_lines;
  }
  void end_frame() override {
    ++frames_ended;
    if (count_lines) BOLO_FUZZ_CHECK(lines_out == lines_in);
    lines_out = 0;
  }

  std::uint64_t frames_begun = 0, frames_ended = 0, total_lines = 0;
  std::uint64_t lines_in = 0, lines_out = 0;
  std::uint64_t checksum = 0;
  bool count_lines = true;  // cleared by a caller that pushes lines outside begin/end

 private:
  std::size_t max_width_;
};

template <class T>
std::unique_ptr<T[]> exact_array(std::size_t n) {
  return std::unique_ptr<T[]>(new T[n == 0 ? 1 : n]);  // new T[0] is fine, but keep it simple
}

// A pipeline configured from the input, with every buffer it is given owned here.
struct FuzzPipeline {
  fw::PipelineConfig config;
  std::unique_ptr<std::uint16_t[]> gain;
  std::unique_ptr<std::int16_t[]> offset;
  std::unique_ptr<std::uint8_t[]> mask;
  std::unique_ptr<fw::Pixel[]> arena;
  std::optional<fw::Pipeline> pipeline;

  // `width`/`height` are the configured frame size (may be 0).
  FuzzPipeline(ByteReader& in, std::uint32_t width, std::uint32_t height, fw::LineSink& out) {
    config.corrector.width = width;
    config.corrector.height = height;
    config.corrector.tau = {in.u32(), in.u32()};
    config.corrector.default_exposure_ns = in.u32();
    config.corrector.default_readout_ns = in.u32();
    config.corrector.nominal_frame_period_ns = in.flag() ? in.u32() : 0;
    const std::uint8_t options = in.u8();
    const std::size_t pixels = std::size_t{width} * height;
    Prng prng(in.u32());
    config.use_nuc = (options & 1) != 0;
    if (config.use_nuc) {
      // Now and then tables shorter than the frame: the stage must refuse to use them.
      const std::size_t n = (options & 0x40) != 0 && pixels > 0 ? pixels - 1 : pixels;
      gain = exact_array<std::uint16_t>(n);
      offset = exact_array<std::int16_t>(n);
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t r = prng.next();
        gain[i] = static_cast<std::uint16_t>(r);
        offset[i] = static_cast<std::int16_t>(r >> 16);
      }
      config.nuc.gain_q14 = std::span<const std::uint16_t>(gain.get(), n);
      config.nuc.offset = std::span<const std::int16_t>(offset.get(), n);
    }
    config.use_bad_pixels = (options & 2) != 0;
    if (config.use_bad_pixels) {
      if ((options & 4) != 0) {
        const std::size_t n = (options & 0x40) != 0 && pixels > 0 ? pixels - 1 : pixels;
        const std::uint8_t density = in.u8();
        mask = exact_array<std::uint8_t>(n);
        for (std::size_t i = 0; i < n; ++i)
          mask[i] = (prng.next() & 0xFF) < density ? 1 : 0;
        config.bad_pixels.mask = std::span<const std::uint8_t>(mask.get(), n);
      }
      config.bad_pixels.detect_stuck = (options & 8) != 0;
      config.bad_pixels.stuck_low = in.u16();
      config.bad_pixels.stuck_high = in.u16();
    }
    std::size_t arena_pixels = fw::Pipeline::arena_pixels(config);
    if ((options & 0x80) != 0) arena_pixels -= std::min<std::size_t>(arena_pixels, in.u8());
    arena = exact_array<fw::Pixel>(arena_pixels);
    for (std::size_t i = 0; i < arena_pixels; ++i) arena[i] = static_cast<fw::Pixel>(prng.next());
    pipeline.emplace(config, std::span<fw::Pixel>(arena.get(), arena_pixels), out);
  }

  fw::LineSink& input() { return pipeline->input(); }
};

}  // namespace bolo::fuzz
