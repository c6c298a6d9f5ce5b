#pragma once
// The two-frame ghosting corrector as a streaming stage. It keeps the previous raw frame in a
// frame store (caller-provided storage) and emits each corrected line as soon as its input line
// has arrived. A frame without a trustworthy predecessor gets no carry-over term, and the reason
// is reported.

#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/firmware/corrector_coefficients.hpp"
#include "bolo/firmware/stage.hpp"

namespace bolo::fw {

// Why a frame was, or was not, corrected against its predecessor.
enum class CarryOver : std::uint8_t {
  applied,                   // corrected against the previous frame
  first_frame,               // nothing before it
  sequence_gap,              // the source's frame counter skipped: frames were dropped
  timestamp_gap,             // the interval exceeds 1.5 nominal frame periods
  timestamp_not_increasing,  // time went backwards or stood still
  ffc_event,                 // a shutter / FFC event happened since the previous frame
  format_change,             // width or height changed
  previous_incomplete,       // the previous frame did not deliver all its lines
  missing_timing,            // no exposure/readout from the frame nor from the configuration
  coefficient_error,         // the timing gives no usable coefficients (see CoefficientStatus)
};
inline constexpr std::size_t kCarryOverReasons = 10;
const char* to_string(CarryOver reason);

struct CorrectorConfig {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  TimeConstants tau;
  // Used where a frame's header has 0 (unknown) exposure / readout; 0 here too = missing.
  std::uint32_t default_exposure_ns = 0;
  std::uint32_t default_readout_ns = 0;
  // Nominal frame period for gap detection; 0 = learn it from the stream.
  std::uint32_t nominal_frame_period_ns = 0;
};

struct CorrectorFrameStats {
  std::uint64_t sequence = 0;
  CarryOver carry_over = CarryOver::first_frame;
  CoefficientStatus coefficient_status = CoefficientStatus::ok;
  CorrectorCoefficients coefficients;
  std::uint32_t saturated_low = 0;   // pixels clamped at 0 (value below -0.5)
  std::uint32_t saturated_high = 0;  // pixels clamped at 65535
  // Lines passed on uncorrected because the frame broke: a row out of order or repeated, a line
  // of the wrong width. The frame is then no predecessor for the next one.
  std::uint32_t rows_uncorrected = 0;
};

struct CorrectorTotals {
  std::uint64_t frames = 0;
  std::uint64_t by_reason[kCarryOverReasons] = {};
  std::uint64_t saturated_low = 0;
  std::uint64_t saturated_high = 0;
};

// The per-pixel kernel: out = sat_u16(round((G * cur - A * prev) / 2^24)), ties away from zero.
// Returns the saturation counts through `low` / `high`.
void correct_line(const Pixel* current, const Pixel* previous, CorrectorCoefficients c,
                  Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high);
// The same, fused with the frame-store update: reads the predecessor from `previous` and
// overwrites it with `current` in the same pass (previous[x] = current[x] once used).
void correct_line_update(const Pixel* current, Pixel* previous, CorrectorCoefficients c,
                         Pixel* out, std::size_t width, std::uint32_t& low, std::uint32_t& high);
// The kernel without a previous frame: out = sat_u16(round(G * cur / 2^24)).
void scale_line(const Pixel* current, std::uint32_t gain_q24, Pixel* out, std::size_t width,
                std::uint32_t& high);

class TwoFrameCorrector final : public Stage {
 public:
  // Output rows per push_lines chunk: about kRunPixels pixels, at least one row, at most the
  // frame. Enough for one kernel call to cover many short lines; small enough to stay in L1.
  static constexpr std::size_t kRunPixels = 4096;
  static constexpr std::size_t run_rows(std::uint32_t width, std::uint32_t height) {
    const std::size_t by_size = width == 0 ? 1 : kRunPixels / width;
    const std::size_t rows = by_size < height ? by_size : height;
    return rows == 0 ? 1 : rows;
  }
  // Pixels of storage the stage needs: the frame store plus run_rows() output lines.
  static constexpr std::size_t storage_pixels(std::uint32_t width, std::uint32_t height) {
    return std::size_t{width} * height + run_rows(width, height) * width;
  }
  // `storage` must hold storage_pixels(config.width, config.height) pixels and outlive the stage.
  TwoFrameCorrector(const CorrectorConfig& config, std::span<Pixel> storage, LineSink& next);

  // Time constants may change between frames (the VO refines them); takes effect next frame.
  void set_time_constants(TimeConstants tau) { config_.tau = tau; }
  const CorrectorConfig& config() const { return config_; }

  void begin_frame(const FrameHeader& header) override;
  void push_line(std::uint32_t row, LineView line) override;
  // Consecutive rows of a carry-over frame go through the kernel in chunks of run_rows() (one
  // call per chunk when the rows are contiguous) and on as runs; anything else line by line.
  void push_lines(std::uint32_t first_row, std::uint32_t count, const Pixel* pixels,
                  std::size_t width, std::size_t stride) override;
  void end_frame() override;

  const CorrectorFrameStats& last_frame() const { return frame_stats_; }
  const CorrectorTotals& totals() const { return totals_; }

 private:
  CarryOver judge_predecessor(const FrameHeader& header) const;
  std::uint32_t learned_period_ns() const;

  enum class Mode : std::uint8_t { full, gain_only, pass_through };

  using UpdateKernel = void (*)(const Pixel*, Pixel*, CorrectorCoefficients, Pixel*, std::size_t,
                                std::uint32_t&, std::uint32_t&);

  CorrectorConfig config_;
  // correct_line_update's implementation for this CPU, looked up once: a 160-pixel line is short
  // enough for the per-call dispatch to show.
  UpdateKernel update_;
  std::span<Pixel> store_;     // previous raw frame, row-major
  std::span<Pixel> out_line_;  // run_rows() corrected lines
  FrameHeader header_{};
  FrameHeader previous_{};
  bool have_previous_ = false;
  bool previous_complete_ = false;
  bool in_frame_ = false;
  bool frame_broken_ = false;      // a row came out of order or at the wrong width
  bool frame_ok_ = false;          // header matches the configured size
  Mode mode_ = Mode::pass_through;
  std::uint32_t lines_seen_ = 0;
  std::uint32_t previous_readout_ns_ = 0;
  static constexpr int kIntervalHistory = 8;
  std::int64_t intervals_ns_[kIntervalHistory] = {};
  int interval_count_ = 0;
  CorrectorFrameStats frame_stats_{};
  CorrectorTotals totals_{};
  // The last coefficient computation and its inputs: a steady exposure and readout (the usual
  // case) asks for the same coefficients every frame, and they are a pure function of these.
  struct CoefficientMemo {
    bool valid = false;
    bool full = false;
    TimeConstants tau{};
    std::uint32_t exposure_ns = 0, readout_ns = 0;
    CoefficientStatus status = CoefficientStatus::ok;
    CorrectorCoefficients coefficients{};
  };
  CoefficientMemo memo_{};
  CoefficientStatus coefficients_for(bool full, std::uint32_t exposure_ns,
                                     std::uint32_t readout_ns, CorrectorCoefficients& out);
};

}  // namespace bolo::fw
