#pragma once
// Helpers for the fault-injection tests: a deterministic synthetic camera, a sink that records
// what went into the pipeline (the "spy"), and one that records what came out.

#include <cstdint>
#include <vector>

#include "bolo/core/frame_source.hpp"
#include "bolo/core/line_sink.hpp"

namespace bolo::test {

// Frame n of a small 14-bit camera, made from n alone (so a second instance gives the same
// frames): a warm gradient, a hot square moving right, hashed noise, two stuck pixels. Per-frame
// exposure and readout vary so a wrong predecessor gives different coefficients, and an FFC
// event comes every `ffc_every` frames (0 = never).
class SyntheticCamera final : public hal::FrameSource {
 public:
  static constexpr std::uint32_t kPeriodNs = 33'333'333;

  SyntheticCamera(std::uint32_t width, std::uint32_t height, std::uint64_t frames,
                  std::uint64_t ffc_every = 0)
      : width_(width), height_(height), frames_(frames), ffc_every_(ffc_every), line_(width) {}

  static std::uint32_t exposure_ns(std::uint64_t n) {
    return 8'000'000 + static_cast<std::uint32_t>(n % 5) * 150'000;
  }
  static std::uint32_t readout_ns(std::uint64_t n) {
    return 20'000'000 + static_cast<std::uint32_t>(n % 7) * 400'000;
  }
  fw::FrameHeader header(std::uint64_t n) const {
    fw::FrameHeader h;
    h.width = width_;
    h.height = height_;
    h.sequence = n;
    h.sequence_valid = true;
    h.timestamp_ns = 1'000'000'000 + static_cast<std::int64_t>(n) * kPeriodNs;
    h.timestamp_valid = true;
    h.exposure_ns = exposure_ns(n);
    h.readout_ns = readout_ns(n);
    h.ffc = ffc_every_ != 0 && n != 0 && n % ffc_every_ == 0 ? fw::FfcState::completed
                                                             : fw::FfcState::none;
    h.fpa_temp_mc = 30'000 + static_cast<std::int32_t>(n % 100);
    return h;
  }
  fw::Pixel pixel(std::uint64_t n, std::uint32_t x, std::uint32_t y) const {
    if (x == 5 && y == 5) return 0x3FFF;  // stuck high
    if (x == width_ - 3 && y == height_ / 2) return 0;  // stuck low
    std::uint64_t h = n * 0x9E3779B97F4A7C15ull ^ (std::uint64_t{y} << 32 | x);
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    std::uint32_t v = 2000 + 30 * x + 20 * y + static_cast<std::uint32_t>(h % 64);
    const std::int64_t square = static_cast<std::int64_t>((n * 3) % (width_ + 8)) - 4;
    if (static_cast<std::int64_t>(x) >= square && static_cast<std::int64_t>(x) < square + 6 &&
        y >= height_ / 3 && y < 2 * height_ / 3)
      v += 3000;
    return static_cast<fw::Pixel>(v);
  }

  hal::SourceFormat format() const override {
    return {width_, height_, 14, hal::PixelUnits::counts, kPeriodNs};
  }
  hal::SourceStats stats() const override { return stats_; }
  hal::StreamStatus stream_frame(fw::LineSink& sink) override {
    if (next_ >= frames_) return hal::StreamStatus::end_of_stream;
    const std::uint64_t n = next_++;
    sink.begin_frame(header(n));
    for (std::uint32_t y = 0; y < height_; ++y) {
      for (std::uint32_t x = 0; x < width_; ++x) line_[x] = pixel(n, x, y);
      sink.push_line(y, fw::LineView(line_.data(), line_.size()));
    }
    sink.end_frame();
    ++stats_.frames_delivered;
    return hal::StreamStatus::frame;
  }
  std::uint64_t position() const { return next_; }

 private:
  std::uint32_t width_, height_;
  std::uint64_t frames_, ffc_every_;
  std::uint64_t next_ = 0;
  std::vector<fw::Pixel> line_;
  hal::SourceStats stats_;
};

// One frame as a sink saw it: header, then every line with its row index, in order.
struct RecordedFrame {
  fw::FrameHeader header{};
  std::vector<std::uint32_t> rows;
  std::vector<std::vector<fw::Pixel>> lines;
  bool ended = false;

  // Every row 0..height-1 exactly once, each `width` pixels long.
  bool complete(std::uint32_t width, std::uint32_t height) const {
    if (rows.size() != height) return false;
    std::vector<bool> seen(height, false);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i] >= height || seen[rows[i]] || lines[i].size() != width) return false;
      seen[rows[i]] = true;
    }
    return true;
  }
  // The first line that is not the frame's (mis-sized or an impossible row), or lines.size().
  // The first line the corrector cannot take: a row out of order (repeated or skipped), beyond
  // the frame, or of the wrong width. From there on it passes lines on unchanged.
  std::size_t first_bad_line(std::uint32_t width, std::uint32_t height) const {
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (rows[i] != i || rows[i] >= height || lines[i].size() != width) return i;
    return rows.size();
  }
  // The last line delivered under `row`, or nullptr.
  const std::vector<fw::Pixel>* line_of_row(std::uint32_t row) const {
    for (std::size_t i = rows.size(); i-- > 0;)
      if (rows[i] == row) return &lines[i];
    return nullptr;
  }
};

// Records every frame it is given; optionally forwards each event to another sink (a spy
// between a source and a pipeline).
class FrameRecorder final : public fw::LineSink {
 public:
  explicit FrameRecorder(fw::LineSink* forward = nullptr) : forward_(forward) {}
  void begin_frame(const fw::FrameHeader& header) override {
    frame_ = RecordedFrame{};
    frame_.header = header;
    if (forward_) forward_->begin_frame(header);
  }
  void push_line(std::uint32_t row, fw::LineView line) override {
    frame_.rows.push_back(row);
    frame_.lines.emplace_back(line.begin(), line.end());
    if (forward_) forward_->push_line(row, line);
  }
  void end_frame() override {
    frame_.ended = true;
    ++frames_;
    if (forward_) forward_->end_frame();
  }
  const RecordedFrame& frame() const { return frame_; }
  std::uint64_t frames() const { return frames_; }

 private:
  fw::LineSink* forward_;
  RecordedFrame frame_;
  std::uint64_t frames_ = 0;
};

}  // namespace bolo::test
