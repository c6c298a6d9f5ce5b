#include "workloads.hpp"

#include <cstring>

namespace bolo::bench {

void FrameFeeder::push_frame(fw::LineSink& sink) {
  const BenchData& d = *data_;
  const std::vector<std::uint16_t>& frame = d.frames[sequence_ % d.frames.size()];
  fw::FrameHeader h;
  h.width = d.width;
  h.height = d.height;
  h.sequence = sequence_;
  h.sequence_valid = true;
  h.timestamp_ns = static_cast<std::int64_t>(sequence_) * kPeriodNs;
  h.timestamp_valid = true;
  h.exposure_ns = kExposureNs;
  h.readout_ns = kReadoutNs;
  h.ffc = fw::FfcState::none;
  h.fpa_temp_mc = 31'250;
  ++sequence_;

  sink.begin_frame(h);
  // The whole frame is in memory: one run, as any source holding a frame should push it.
  sink.push_lines(0, d.height, frame.data(), d.width, d.width);
  sink.end_frame();
}

fw::CorrectorConfig bench_corrector_config(std::uint32_t width, std::uint32_t height) {
  fw::CorrectorConfig c;
  c.width = width;
  c.height = height;
  c.tau = {11'000'000, 13'000'000};  // tau_h, tau_c: typical for a 12 um VOx pixel
  c.nominal_frame_period_ns = FrameFeeder::kPeriodNs;
  return c;
}

// ---- memcpy ----

MemcpyWorkload::MemcpyWorkload(const BenchData& data)
    : data_(&data), dst_(std::size_t{data.width} * data.height) {}

void MemcpyWorkload::run(std::size_t frames) {
  const std::size_t bytes = dst_.size() * sizeof(std::uint16_t);
  for (std::size_t f = 0; f < frames; ++f) {
    std::memcpy(dst_.data(), data_->frames[next_].data(), bytes);
    clobber_memory(dst_.data());
    next_ = (next_ + 1) % data_->frames.size();
  }
}

// ---- corrector ----

CorrectorWorkload::CorrectorWorkload(const BenchData& data)
    : feeder_(data),
      storage_(fw::TwoFrameCorrector::storage_pixels(data.width, data.height)),
      corrector_(bench_corrector_config(data.width, data.height), storage_, sink_) {
  // Warm-up: the first frame has no predecessor (gain only); from the second on, carry-over.
  for (int i = 0; i < 2; ++i) feeder_.push_frame(corrector_);
}

void CorrectorWorkload::run(std::size_t frames) {
  for (std::size_t f = 0; f < frames; ++f) {
    feeder_.push_frame(corrector_);
    not_applied_ += corrector_.last_frame().carry_over != fw::CarryOver::applied ? 1u : 0u;
  }
}

// ---- pipeline ----

fw::PipelineConfig PipelineWorkload::config_for(const BenchData& data) {
  fw::PipelineConfig c;
  c.corrector = bench_corrector_config(data.width, data.height);
  c.use_nuc = true;
  c.nuc.gain_q14 = data.nuc_gain_q14;
  c.nuc.offset = data.nuc_offset;
  c.use_bad_pixels = true;
  c.bad_pixels.mask = data.bad_mask;
  c.bad_pixels.detect_stuck = true;
  return c;
}

PipelineWorkload::PipelineWorkload(const BenchData& data)
    : feeder_(data),
      config_(config_for(data)),
      arena_(fw::Pipeline::arena_pixels(config_)),
      pipeline_(config_, arena_, sink_) {
  for (int i = 0; i < 2; ++i) feeder_.push_frame(pipeline_.input());
}

void PipelineWorkload::run(std::size_t frames) {
  for (std::size_t f = 0; f < frames; ++f) {
    feeder_.push_frame(pipeline_.input());
    not_applied_ +=
        pipeline_.corrector().last_frame().carry_over != fw::CarryOver::applied ? 1u : 0u;
  }
}

}  // namespace bolo::bench
