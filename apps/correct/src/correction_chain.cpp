#include "correction_chain.hpp"

#include <cmath>

#include "bolo/correct/fail.hpp"

namespace bolo::correct {
namespace {

fw::PipelineConfig with_nuc(fw::PipelineConfig config, const NucFile& nuc) {
  if (!nuc.gain_q14.empty()) {
    config.use_nuc = true;
    config.nuc = nuc.tables();
  }
  return config;
}

double q24(std::uint32_t value) {
  return std::ldexp(static_cast<double>(value), -int{fw::kCoefficientFractionBits});
}

}  // namespace

fw::PipelineConfig pipeline_config(const Setup& setup, const hal::SourceFormat& format, bool bad_pixels,
                                   const std::string& input) {
  // Tone-mapped video (a camera's AGC output) is not a linear function of the scene: the carry-over
  // model would correct it wrongly, so it is refused rather than warned about.
  if (format.units == hal::PixelUnits::counts8)
    fail(input, ": units counts8 (8-bit tone-mapped video, e.g. V4L2 GREY/YUYV/UYVY): the correction needs the "
                "sensor's linear counts; record the camera's Y16 (v4l2:/dev/videoN?format=Y16)");
  fw::PipelineConfig config;
  config.corrector.width = format.width;
  config.corrector.height = format.height;
  config.corrector.tau = setup.tau;
  config.corrector.default_exposure_ns = setup.exposure.ns;
  config.corrector.default_readout_ns = setup.readout.ns;
  config.corrector.nominal_frame_period_ns = setup.nominal_period_ns;
  config.use_bad_pixels = bad_pixels;
  const std::uint32_t bits = format.bits;
  config.bad_pixels.stuck_high = static_cast<fw::Pixel>(bits >= 16 || bits == 0 ? 0xFFFFu : (1u << bits) - 1u);
  config.bad_pixels.width = format.width;
  config.bad_pixels.height = format.height;
  return config;
}

CorrectionChain::CorrectionChain(const fw::PipelineConfig& config, const CorrectRequest& request,
                                 std::string input)
    : request_(request),
      input_name_(std::move(input)),
      nuc_(request.nuc ? read_nuc_file(*request.nuc, config.corrector.width, config.corrector.height) : NucFile{}),
      config_(with_nuc(config, nuc_)),
      arena_(fw::Pipeline::arena_pixels(config_)),
      corrected_storage_(fw::FrameCollector::storage_pixels(config.corrector.width, config.corrector.height)),
      corrected_(config.corrector.width, config.corrector.height, corrected_storage_),
      pipeline_(config_, arena_, corrected_),
      raw_storage_(fw::FrameCollector::storage_pixels(config.corrector.width, config.corrector.height)),
      raw_(config.corrector.width, config.corrector.height, raw_storage_) {
  if (!request.float_output) return;
  const std::uint32_t width = config.corrector.width, height = config.corrector.height;
  fw::LineSink* reference_input = &raw_;
  if (request.bad_pixels) {
    float_bad_storage_.resize(fw::BadPixelStage::storage_pixels(width, height));
    float_bad_pixels_.emplace(config.bad_pixels, float_bad_storage_, raw_);
    reference_input = &*float_bad_pixels_;
  }
  if (config_.use_nuc) {  // in front of the bad pixels, as in the pipeline
    float_nuc_storage_.resize(fw::NucStage::storage_pixels(width));
    float_nuc_.emplace(width, height, config_.nuc, float_nuc_storage_, *reference_input);
    reference_input = &*float_nuc_;
  }
  tee_.emplace(pipeline_.input(), *reference_input);
  std::optional<double> nominal_period_s;
  if (request.nominal_fps) nominal_period_s = 1.0 / *request.nominal_fps;
  reference_.emplace(width, height, request.tau_h_s, request.tau_c_s, request.exposure_s, request.readout_s,
                     nominal_period_s);
  reference_out_.resize(std::size_t{width} * height);
  float_frame_.resize(reference_out_.size());
}

FrameStats CorrectionChain::pipeline_stats(std::uint64_t i, const FrameTiming& timing) {
  const fw::CorrectorFrameStats& cs = pipeline_.corrector().last_frame();
  FrameStats s;
  s.frame = i;
  s.carry_over = cs.carry_over;
  s.coefficient_status = cs.coefficient_status;
  s.gain = q24(cs.coefficients.gain_q24);
  s.carry = q24(cs.coefficients.carry_q24);
  s.saturated_low = cs.saturated_low;
  s.saturated_high = cs.saturated_high;
  s.exposure_from_flag = timing.exposure_from_flag;
  s.readout_from_flag = timing.readout_from_flag;
  if (const fw::BadPixelStage* bad = pipeline_.bad_pixels()) {
    s.bad_pixels_replaced = bad->last_frame().replaced;
    s.bad_pixels_unrepairable = bad->last_frame().unrepairable;
  }
  return s;
}

void CorrectionChain::run_reference(const rec::FrameRow& row, const FrameTiming& timing,
                                    const FrameTiming* previous, FrameStats& s) {
  if (!raw_.complete()) fail(input_name_, ": frame ", s.frame, ": incomplete frame for the reference");
  const sim::ReferenceFrameInfo info{row.index, row.t_s, timing.exposure_s, timing.readout_s,
                                     row.ffc.value_or(false)};
  const bool applied = reference_->process(info, raw_.pixels(), reference_out_);
  s.reference_disagrees = applied != (s.carry_over == fw::CarryOver::applied);
  const double g = 1.0 / (1.0 - std::exp(-timing.exposure_s / request_.tau_h_s));
  s.gain = g;
  // The reference applies the carry only after a first frame, which has a predecessor's timing.
  s.carry = applied && previous != nullptr ? g * std::exp(-previous->readout_s / request_.tau_c_s) : 0.0;
  s.saturated_low = s.saturated_high = 0;
  for (std::size_t p = 0; p < reference_out_.size(); ++p) {
    float_frame_[p] = static_cast<float>(reference_out_[p]);
    s.saturated_low += reference_out_[p] <= 0.0;
    s.saturated_high += reference_out_[p] >= 65535.0;
  }
}

FrameStats CorrectionChain::finish_frame(std::uint64_t i, const rec::FrameRow& row, const FrameTiming& timing,
                                         const FrameTiming* previous) {
  if (!corrected_.complete()) fail(input_name_, ": frame ", i, ": the pipeline delivered an incomplete frame");
  FrameStats s = pipeline_stats(i, timing);
  if (reference_) run_reference(row, timing, previous, s);
  return s;
}

void CorrectionChain::append(rec::RecordingWriter& writer, const rec::FrameRow& row) const {
  if (reference_)
    writer.append(std::span<const float>(float_frame_), row);
  else
    writer.append(corrected_.pixels(), row);
}

}  // namespace bolo::correct
