#include "bolo/hal/lepton_telemetry.hpp"

#include "bolo/firmware/frame_header.hpp"

namespace bolo::hal {
namespace {

std::uint32_t u32_low_first(std::span<const std::uint16_t> w, std::size_t at) {
  return std::uint32_t{w[at]} | (std::uint32_t{w[at + 1]} << 16);
}

}  // namespace

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

std::int32_t centikelvin_to_mc(std::uint16_t ck) {
  if (ck == 0) return fw::kUnknownTemperature;
  return static_cast<std::int32_t>(ck) * 10 - 273150;
}

}  // namespace bolo::hal
