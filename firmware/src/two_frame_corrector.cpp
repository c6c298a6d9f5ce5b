#include "bolo/firmware/two_frame_corrector.hpp"

#include <algorithm>

#include "bolo/firmware/carry_over_rule.hpp"
#include "bolo/firmware/detail/kernels.hpp"

namespace bolo::fw {

const char* to_string(CarryOver reason) {
  switch (reason) {
    case CarryOver::applied: return "applied";
    case CarryOver::first_frame: return "first_frame";
    case CarryOver::sequence_gap: return "sequence_gap";
    case CarryOver::timestamp_gap: return "timestamp_gap";
    case CarryOver::timestamp_not_increasing: return "timestamp_not_increasing";
    case CarryOver::ffc_event: return "ffc_event";
    case CarryOver::format_change: return "format_change";
    case CarryOver::previous_incomplete: return "previous_incomplete";
    case CarryOver::missing_timing: return "missing_timing";
    case CarryOver::coefficient_error: return "coefficient_error";
  }
  return "unknown";
}

TwoFrameCorrector::TwoFrameCorrector(const CorrectorConfig& config, std::span<Pixel> storage,
                                     LineSink& next)
    : Stage(next),
      config_(config),
      update_(detail::correct_update_kernel(detail::selected_kernel_path())) {
  const std::size_t frame = std::size_t{config.width} * config.height;
  // A short arena is a configuration bug; use what fits so nothing writes past it, and let
  // every frame fail the size check below.
  if (storage.size() < storage_pixels(config.width, config.height)) {
    config_.width = 0;
    config_.height = 0;
    return;
  }
  store_ = storage.subspan(0, frame);
  out_line_ = storage.subspan(frame, run_rows(config.width, config.height) * config.width);
}

namespace {

// later - earlier for later > earlier, exact even where the signed difference would overflow
// (timestamps far apart, e.g. a clock that jumped): unsigned arithmetic wraps by definition.
std::uint64_t interval_ns(std::int64_t earlier, std::int64_t later) {
  return static_cast<std::uint64_t>(later) - static_cast<std::uint64_t>(earlier);
}

}  // namespace

CarryOver carry_over_between(const FrameHeader& previous, const FrameHeader& current, std::uint64_t period_ns) {
  if (shutter_event(current.ffc)) return CarryOver::ffc_event;
  if (current.sequence_valid && previous.sequence_valid && current.sequence != previous.sequence + 1)
    return CarryOver::sequence_gap;
  if (current.timestamp_valid && previous.timestamp_valid) {
    if (current.timestamp_ns <= previous.timestamp_ns) return CarryOver::timestamp_not_increasing;
    const std::uint64_t interval = interval_ns(previous.timestamp_ns, current.timestamp_ns);
    // 2 * interval > 3 * period without overflow: interval > floor(3 * period / 2)
    if (period_ns != 0 && interval > period_ns * 3 / 2) return CarryOver::timestamp_gap;
  }
  return CarryOver::applied;
}

std::uint32_t TwoFrameCorrector::learned_period_ns() const {
  if (config_.nominal_frame_period_ns != 0) return config_.nominal_frame_period_ns;
  if (interval_count_ == 0) return 0;
  // Median of the recent intervals: robust to jitter and to the occasional gap itself.
  std::int64_t sorted[kIntervalHistory];
  const int n = std::min(interval_count_, kIntervalHistory);
  for (int i = 0; i < n; ++i) {  // insertion sort: at most 8 values
    const std::int64_t v = intervals_ns_[i];
    int j = i;
    for (; j > 0 && sorted[j - 1] > v; --j) sorted[j] = sorted[j - 1];
    sorted[j] = v;
  }
  const std::int64_t median = sorted[n / 2];
  return median > 0xFFFFFFFF ? 0xFFFFFFFFu : static_cast<std::uint32_t>(median);
}

CarryOver TwoFrameCorrector::judge_predecessor(const FrameHeader& header) const {
  if (!frame_ok_) return CarryOver::format_change;
  if (!have_previous_) return CarryOver::first_frame;
  if (previous_.width != header.width || previous_.height != header.height)
    return CarryOver::format_change;
  if (!previous_complete_) return CarryOver::previous_incomplete;
  return carry_over_between(previous_, header, learned_period_ns());
}

// compute_coefficients (full) or compute_gain_only, or their last answer for the same inputs.
// Like them, `out` is written only when the status is ok.
CoefficientStatus TwoFrameCorrector::coefficients_for(bool full, std::uint32_t exposure_ns,
                                                      std::uint32_t readout_ns,
                                                      CorrectorCoefficients& out) {
  const TimeConstants tau = config_.tau;
  if (!(memo_.valid && memo_.full == full && memo_.tau.heating_ns == tau.heating_ns &&
        memo_.tau.cooling_ns == tau.cooling_ns && memo_.exposure_ns == exposure_ns &&
        (!full || memo_.readout_ns == readout_ns))) {
    memo_.valid = true;
    memo_.full = full;
    memo_.tau = tau;
    memo_.exposure_ns = exposure_ns;
    memo_.readout_ns = readout_ns;
    memo_.status = full ? compute_coefficients(tau, exposure_ns, readout_ns, memo_.coefficients)
                        : compute_gain_only(tau, exposure_ns, memo_.coefficients);
  }
  if (memo_.status == CoefficientStatus::ok) out = memo_.coefficients;
  return memo_.status;
}

void TwoFrameCorrector::begin_frame(const FrameHeader& header) {
  header_ = header;
  in_frame_ = true;
  lines_seen_ = 0;
  frame_broken_ = false;
  frame_ok_ = header.width == config_.width && header.height == config_.height &&
              config_.width != 0;

  frame_stats_ = CorrectorFrameStats{};
  frame_stats_.sequence = header.sequence;
  CarryOver reason = judge_predecessor(header);

  const std::uint32_t exposure =
      header.exposure_ns != 0 ? header.exposure_ns : config_.default_exposure_ns;
  mode_ = Mode::pass_through;
  if (frame_ok_) {
    if (exposure == 0) {
      reason = CarryOver::missing_timing;
    } else if (reason == CarryOver::applied && previous_readout_ns_ == 0) {
      reason = CarryOver::missing_timing;
      mode_ = Mode::gain_only;
    } else {
      mode_ = reason == CarryOver::applied ? Mode::full : Mode::gain_only;
    }
    if (mode_ != Mode::pass_through) {
      const CoefficientStatus status = coefficients_for(
          mode_ == Mode::full, exposure, previous_readout_ns_, frame_stats_.coefficients);
      frame_stats_.coefficient_status = status;
      if (status != CoefficientStatus::ok) {
        reason = CarryOver::coefficient_error;
        mode_ = Mode::pass_through;
      }
    }
  }
  frame_stats_.carry_over = reason;

  if (header.timestamp_valid && previous_.timestamp_valid && have_previous_ &&
      header.timestamp_ns > previous_.timestamp_ns) {
    const std::uint64_t interval = interval_ns(previous_.timestamp_ns, header.timestamp_ns);
    {
      intervals_ns_[interval_count_ % kIntervalHistory] =
          interval > INT64_MAX ? INT64_MAX : static_cast<std::int64_t>(interval);
      ++interval_count_;
      if (interval_count_ >= 2 * kIntervalHistory) interval_count_ -= kIntervalHistory;
    }
  }
  next().begin_frame(header);
}

void TwoFrameCorrector::push_line(std::uint32_t row, LineView line) {
  // Rows must come in order, each once, at the configured width: a repeated or skipped row would
  // leave a stale row of an older frame in the store. Anything else is passed on unchanged and
  // the frame never becomes a complete predecessor.
  if (!frame_ok_ || frame_broken_ || row != lines_seen_ || row >= config_.height ||
      line.size() != config_.width) {
    if (frame_ok_ && !frame_broken_) frame_broken_ = true;
    ++frame_stats_.rows_uncorrected;
    next().push_line(row, line);
    return;
  }
  Pixel* stored = store_.data() + std::size_t{row} * config_.width;
  // The raw line becomes the next frame's predecessor: the model ghosts raw values, not outputs.
  switch (mode_) {
    case Mode::full:  // reads the stored row and replaces it with this line in one pass
      update_(line.data(), stored, frame_stats_.coefficients, out_line_.data(), line.size(),
              frame_stats_.saturated_low, frame_stats_.saturated_high);
      break;
    case Mode::gain_only:
      scale_line(line.data(), frame_stats_.coefficients.gain_q24, out_line_.data(), line.size(),
                 frame_stats_.saturated_high);
      std::copy(line.begin(), line.end(), stored);
      break;
    case Mode::pass_through:
      std::copy(line.begin(), line.end(), out_line_.begin());
      std::copy(line.begin(), line.end(), stored);
      break;
  }
  ++lines_seen_;
  next().push_line(row, LineView(out_line_.data(), line.size()));
}

void TwoFrameCorrector::push_lines(std::uint32_t first_row, std::uint32_t count,
                                   const Pixel* pixels, std::size_t width, std::size_t stride) {
  // Only the steady state takes the run path: in-order rows of a good frame, all within the
  // height, at the configured width, with carry-over. Every other case (broken frames, the first
  // frame, rows past the end) is the line path, so its outcome is push_line's by construction.
  if (mode_ != Mode::full || !frame_ok_ || frame_broken_ || first_row != lines_seen_ ||
      width != config_.width || count > config_.height - first_row) {
    LineSink::push_lines(first_row, count, pixels, width, stride);
    return;
  }
  const std::uint32_t chunk = static_cast<std::uint32_t>(out_line_.size() / width);
  for (std::uint32_t done = 0; done < count;) {
    const std::uint32_t rows = std::min(chunk, count - done);
    const std::uint32_t row = first_row + done;
    const Pixel* in = pixels + std::size_t{done} * stride;
    Pixel* stored = store_.data() + std::size_t{row} * width;
    if (stride == width) {  // the run, the store rows and the output rows are all contiguous
      update_(in, stored, frame_stats_.coefficients, out_line_.data(), std::size_t{rows} * width,
              frame_stats_.saturated_low, frame_stats_.saturated_high);
    } else {
      for (std::uint32_t i = 0; i < rows; ++i)
        update_(in + std::size_t{i} * stride, stored + std::size_t{i} * width,
                frame_stats_.coefficients, out_line_.data() + std::size_t{i} * width, width,
                frame_stats_.saturated_low, frame_stats_.saturated_high);
    }
    lines_seen_ += rows;
    next().push_lines(row, rows, out_line_.data(), width, width);
    done += rows;
  }
}

void TwoFrameCorrector::end_frame() {
  if (in_frame_) {
    // A frame of the configured size that broke mid-way is an incomplete predecessor (not
    // "nothing before"): the next frame says previous_incomplete.
    have_previous_ = frame_ok_;
    previous_complete_ = frame_ok_ && !frame_broken_ && lines_seen_ == config_.height;
    previous_ = header_;
    previous_readout_ns_ =
        header_.readout_ns != 0 ? header_.readout_ns : config_.default_readout_ns;
    ++totals_.frames;
    ++totals_.by_reason[static_cast<std::size_t>(frame_stats_.carry_over)];
    totals_.saturated_low += frame_stats_.saturated_low;
    totals_.saturated_high += frame_stats_.saturated_high;
    in_frame_ = false;
  }
  next().end_frame();
}

}  // namespace bolo::fw
