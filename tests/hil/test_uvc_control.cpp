// The PureThermal emulator's pure parts: the UVC probe/commit control as uvcvideo reads it, the
// negotiation, and telemetry rows the project's Lepton decoder reads back.

#include <catch2/catch.hpp>

#include "bolo/hal/lepton_telemetry.hpp"
#include "emulators/uvc_control.hpp"
#include "emulators/uvc_frames.hpp"

using namespace bolo::hil::uvc;

TEST_CASE("uvc: the probe/commit control is laid out as UVC 1.1 says, little endian", "[hil][uvc]") {
  StreamingControl c;
  c.hint = 0x0102;
  c.format_index = 1;
  c.frame_index = 2;
  c.frame_interval = 1111111;  // 0x0010F447
  c.max_video_frame_size = 39040;  // 0x00009880
  c.max_payload_transfer_size = 40960;  // 0x0000A000
  c.clock_frequency = 48000000;
  c.framing_info = 3;
  c.max_version = 1;
  const auto b = c.encode(StreamingControl::kBytes);
  REQUIRE(b.size() == 34);
  CHECK(b[0] == 0x02);
  CHECK(b[1] == 0x01);
  CHECK(b[2] == 1);
  CHECK(b[3] == 2);
  CHECK((b[4] | b[5] << 8 | b[6] << 16 | b[7] << 24) == 1111111);
  CHECK((b[18] | b[19] << 8 | b[20] << 16 | b[21] << 24) == 39040);
  CHECK((b[22] | b[23] << 8 | b[24] << 16 | b[25] << 24) == 40960);
  CHECK(b[30] == 3);
  CHECK(b[33] == 1);
  CHECK(c.encode(26).size() == 26);  // a UVC 1.0 host reads 26 bytes
  CHECK(StreamingControl::decode(b, {}) == c);
  // Bytes a short (UVC 1.0) SET_CUR does not reach keep their value.
  StreamingControl base;
  base.clock_frequency = 7;
  const StreamingControl short_set = StreamingControl::decode(std::span(b).first(26), base);
  CHECK(short_set.max_payload_transfer_size == 40960);
  CHECK(short_set.clock_frequency == 7);
}

TEST_CASE("uvc: a probe settles on the PureThermal's frames, sizes and payload", "[hil][uvc]") {
  StreamingControl asked;
  asked.format_index = 1;
  asked.frame_index = 2;
  asked.max_payload_transfer_size = 3;  // the device decides this
  const StreamingControl s = settle(asked, 40960);
  CHECK(s.frame_index == 2);
  CHECK(frame_of(s).height == 122);
  CHECK(s.max_video_frame_size == 160 * 122 * 2);
  CHECK(s.max_payload_transfer_size == 40960);
  CHECK(s.frame_interval == kFrameInterval);
  asked.frame_index = 9;  // no such frame: the first
  CHECK(settle(asked, 40960).frame_index == 1);
  asked.frame_index = 2;
  asked.format_index = 2;  // no such format
  CHECK(settle(asked, 40960).frame_index == 1);
  CHECK(frame_of(settle(asked, 40960)).bytes() == 38400);
}

TEST_CASE("uvc: GET requests on probe/commit are answered, others stalled", "[hil][uvc]") {
  const StreamingControl cur = settle({.format_index = 1, .frame_index = 2}, 40960);
  CHECK(answer(kGetCur, kProbe, 34, cur, 40960) == cur.encode(34));
  CHECK(answer(kGetCur, kCommit, 26, cur, 40960)->size() == 26);
  CHECK(StreamingControl::decode(*answer(kGetDef, kProbe, 34, cur, 40960), {}).frame_index == 1);
  CHECK(StreamingControl::decode(*answer(kGetMin, kProbe, 34, cur, 40960), {}).frame_index == 1);
  CHECK(StreamingControl::decode(*answer(kGetMax, kProbe, 34, cur, 40960), {}).frame_index == 2);
  CHECK(answer(kGetLen, kProbe, 2, cur, 40960) == std::vector<std::uint8_t>{34, 0});
  CHECK(answer(kGetInfo, kProbe, 1, cur, 40960) == std::vector<std::uint8_t>{3});
  CHECK_FALSE(answer(kGetCur, 3, 34, cur, 40960).has_value());  // not probe/commit
  CHECK_FALSE(answer(0x05, kProbe, 34, cur, 40960).has_value());
}

TEST_CASE("uvc: telemetry rows read back with the project's Lepton decoder", "[hil][uvc]") {
  Telemetry t;
  t.frame_counter = 0x12345;
  t.uptime_ms = 0xABCDE;
  t.time_at_last_ffc_ms = 0x10001;
  const FrameFeed feed("");  // simulated images
  const Bytes f = feed.frame(3, {160, 122}, t);
  REQUIRE(f.size() == 160 * 122 * 2);
  std::vector<std::uint16_t> row_a(80);
  for (std::size_t x = 0; x < 80; ++x) row_a[x] = static_cast<std::uint16_t>(f[2 * (19200 + x)] | f[2 * (19200 + x) + 1] << 8);
  bolo::hal::LeptonTelemetry out;
  REQUIRE(bolo::hal::decode_lepton_telemetry(row_a, out));
  CHECK(out.frame_counter == 0x12345);
  CHECK(out.uptime_ms == 0xABCDE);
  CHECK(out.time_at_last_ffc_ms == 0x10001);
  CHECK(out.ffc_state == bolo::hal::LeptonFfcState::complete);
  CHECK(out.fpa_temp_ck == t.fpa_temp_ck);
  CHECK(out.housing_temp_ck == t.housing_temp_ck);
  // The image part is the same with or without the telemetry rows, and frames differ.
  const Bytes plain = feed.frame(3, {160, 120}, t);
  CHECK(std::equal(plain.begin(), plain.end(), f.begin()));
  CHECK(feed.frame(4, {160, 120}, t) != plain);
  CHECK_THROWS_WITH(FrameFeed("/nonexistent-recording"), Catch::Contains("/nonexistent-recording"));
}
