#include "bolo/hal/lepton_telemetry.hpp"

#include "bolo/core/frame_header.hpp"

namespace bolo::hal {
namespace {

std::uint32_t u32_low_first(std::span<const std::uint16_t> w, std::size_t at) {
  return std::uint32_t{w[at]} | (std::uint32_t{w[at + 1]} << 16);
}

}  // namespace

std::uint32_t lepton_telemetry_rows(std::uint32_t width, std::uint32_t height) {
  if (width == 160 && height == 122) return 2;
  if (width == 80 && height == 63) return 3;
  return 0;
}

bool decode_lepton_telemetry(std::span<const std::uint16_t> row_a, LeptonTelemetry& out) {
  if (row_a.size() < kLeptonTelemetryWords) return false;
  LeptonTelemetry t;
  t.revision = row_a[0];
  t.uptime_ms = u32_low_first(row_a, 1);
  t.status = u32_low_first(row_a, 3);
  t.ffc_desired = (t.status >> 3) & 1u;
  t.ffc_state = static_cast<LeptonFfcState>((t.status >> 4) & 3u);
  t.agc_on = (t.status >> 12) & 1u;
  t.shutter_lockout = (t.status >> 15) & 1u;
  t.frame_counter = u32_low_first(row_a, 20);
  t.fpa_counts = row_a[23];
  t.fpa_temp_ck = row_a[24];
  t.housing_temp_ck = row_a[26];
  t.fpa_temp_last_ffc_ck = row_a[29];
  t.time_at_last_ffc_ms = u32_low_first(row_a, 30);
  out = t;
  return true;
}

fw::FfcState LeptonFfcTracker::next(const LeptonTelemetry& t) {
  const bool new_stamp = have_ && t.time_at_last_ffc_ms != last_ffc_ms_;
  const bool after_ffc = in_progress_;
  have_ = true;
  last_ffc_ms_ = t.time_at_last_ffc_ms;
  in_progress_ = t.ffc_state == LeptonFfcState::in_progress;
  if (in_progress_) return fw::FfcState::in_progress;
  if (new_stamp || after_ffc) return fw::FfcState::completed;
  return t.ffc_state == LeptonFfcState::imminent ? fw::FfcState::imminent : fw::FfcState::none;
}

std::int32_t centikelvin_to_mc(std::uint16_t ck) {
  if (ck == 0) return fw::kUnknownTemperature;
  return static_cast<std::int32_t>(ck) * 10 - 273150;
}

LeptonFrameCounter::Step LeptonFrameCounter::add(std::uint32_t counter) {
  if (!have_) {
    have_ = true;
    start_at(counter);
    return Step::first;
  }
  const auto step = static_cast<std::int32_t>(counter - highest_);  // the 32-bit counter may wrap
  Step s = Step::repeat;
  if (step > 0) s = forward_by(static_cast<std::uint32_t>(step));
  if (step < 0) s = behind_by(0u - static_cast<std::uint32_t>(step));
  switch (s) {
    case Step::forward: highest_ = counter; break;
    case Step::repeat: ++repeats_; break;
    case Step::late: ++late_; break;
    case Step::jump:
      ++jumps_;
      start_at(counter);  // the stride is kept: the same camera, counting from elsewhere
      break;
    case Step::first: break;
  }
  return s;
}

void LeptonFrameCounter::restart() {
  have_ = false;
  stride_ = 0;
}

void LeptonFrameCounter::start_at(std::uint32_t counter) {
  highest_ = counter;
  delivered_ = 1;
  advanced_ = 0;
}

LeptonFrameCounter::Step LeptonFrameCounter::forward_by(std::uint32_t step) {
  if (stride_ == 0 || step < stride_) {
    if (step > kLeptonMaxStride) return Step::jump;
    // The camera's step shows for the first time (or is smaller than believed: the earlier
    // steps held gaps). The window's slots were in the old step, so it starts over with this
    // frame and the previous highest, one step behind.
    stride_ = step;
    advanced_ = 1;
    delivered_ = 0b11;
    return Step::forward;
  }
  const std::uint32_t frames = (step + stride_ / 2) / stride_;
  if (frames > kLeptonCounterWindow) return Step::jump;
  advanced_ = frames;
  delivered_ = (frames < kLeptonCounterWindow ? delivered_ << frames : 0) | 1u;
  return Step::forward;
}

// Behind the highest: a frame not delivered yet is late, one delivered already a repeat.
LeptonFrameCounter::Step LeptonFrameCounter::behind_by(std::uint32_t step) {
  if (stride_ == 0) return step > kLeptonMaxStride ? Step::jump : Step::late;
  // Less than a stride behind: the stride was learned over a gap (two frames swapped at the
  // start), so this frame lies between delivered ones; rounding would take it for one of them.
  if (step < stride_) return Step::late;
  const std::uint32_t frames = (step + stride_ / 2) / stride_;
  if (frames >= kLeptonCounterWindow) return Step::jump;  // beyond the window (and the 64 bits that keep it)
  const std::uint64_t bit = std::uint64_t{1} << frames;
  if ((delivered_ & bit) != 0) return Step::repeat;
  delivered_ |= bit;
  return Step::late;
}

}  // namespace bolo::hal
