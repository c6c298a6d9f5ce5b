// Lepton telemetry row A: each field from its words (usb-thermal-cores.md).

#include <catch2/catch.hpp>

#include <array>

#include "bolo/firmware/frame_header.hpp"
#include "bolo/hal/lepton_telemetry.hpp"

using namespace bolo::hal;

TEST_CASE("lepton telemetry: status bits, counters and temperatures", "[hal][telemetry]") {
  std::array<std::uint16_t, 80> w{};
  w[1] = 0x5678; w[2] = 0x0012;  // uptime
  w[3] = (1u << 3) | (2u << 4) | (1u << 12) | (1u << 15);
  w[4] = 0x0001;
  w[20] = 0xFFFF; w[21] = 0x0002;
  w[23] = 1234; w[24] = 30015; w[26] = 30100; w[29] = 29999;
  w[30] = 0x0010; w[31] = 0x0001;
  LeptonTelemetry t;
  REQUIRE(decode_lepton_telemetry(w, t));
  CHECK(t.uptime_ms == 0x00125678u);
  CHECK(t.status == 0x00019028u);
  CHECK(t.ffc_desired);
  CHECK(t.ffc_state == LeptonFfcState::in_progress);
  CHECK(t.agc_on);
  CHECK(t.shutter_lockout);
  CHECK(t.frame_counter == 0x0002FFFFu);
  CHECK(t.fpa_counts == 1234);
  CHECK(t.fpa_temp_ck == 30015);
  CHECK(t.housing_temp_ck == 30100);
  CHECK(t.fpa_temp_last_ffc_ck == 29999);
  CHECK(t.time_at_last_ffc_ms == 0x00010010u);
  CHECK(centikelvin_to_mc(30015) == 27000);  // 300.15 K = 27.000 °C
  CHECK(centikelvin_to_mc(0) == bolo::fw::kUnknownTemperature);

  w[3] = 0;
  REQUIRE(decode_lepton_telemetry(w, t));
  CHECK(t.ffc_state == LeptonFfcState::never);
  CHECK_FALSE(t.ffc_desired);
}

TEST_CASE("lepton telemetry: a short row is refused and leaves the output alone", "[hal][telemetry]") {
  std::array<std::uint16_t, 79> w{};
  LeptonTelemetry t;
  t.frame_counter = 7;
  CHECK_FALSE(decode_lepton_telemetry(w, t));
  CHECK(t.frame_counter == 7);
}
