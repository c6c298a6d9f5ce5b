// FlirOneReassembler on synthetic frames: good frames in any transfer split, and every fault the
// rules name (truncated, stray, trailing, bad header, row id, CRC) counted and not delivered.

#include <catch2/catch.hpp>

#include "bolo/hal/flirone_reassembler.hpp"
#include "flirone_frames.hpp"

using namespace bolo;
using hal::FlirOneReassembler;
using test::make_flirone_frame;

namespace {

std::size_t push_all(FlirOneReassembler& r, const std::vector<std::vector<std::uint8_t>>& transfers) {
  std::size_t frames = 0;
  for (const auto& t : transfers) {
    frames += r.push_transfer(t) ? 1 : 0;
    while (r.poll()) ++frames;
  }
  return frames;
}

}  // namespace

TEST_CASE("flirone: a frame comes out whole whatever the transfer sizes", "[hal][flirone]") {
  const auto frame = make_flirone_frame();
  for (std::size_t chunk : {std::size_t{28}, std::size_t{164}, std::size_t{4096}, std::size_t{16384},
                            std::size_t{65536}, frame.size()}) {
    INFO("chunk " << chunk);
    FlirOneReassembler r;
    std::vector<std::vector<std::uint8_t>> transfers;
    test::split_into_transfers(frame, chunk, transfers);
    transfers.emplace_back();  // the zero-length transfer that follows a frame
    test::split_into_transfers(make_flirone_frame({.base = 5000}), chunk, transfers);
    CHECK(push_all(r, transfers) == 2);
    const hal::FlirOneFrame& f = r.frame();
    CHECK(f.pixels[0] == 5000);
    CHECK(f.pixels[79 + 80 * 59] == 5000 + 79 + 80 * 59);
    CHECK(f.lepton.frame_counter == 100);
    CHECK(f.lepton.fpa_temp_ck == 32000);
    CHECK(std::string(f.status.ffc_state) == "FFC_VALID_RAD");
    CHECK(f.status.usb_timestamp_ns == 100'250'000'000);
    CHECK(f.jpeg.size() == 300);
    CHECK(f.jpeg[1] == 7);
    CHECK(r.counters().frames == 2);
    CHECK(r.counters().stray_transfers == 0);
    CHECK(r.counters().truncated == 0);
  }
}

TEST_CASE("flirone: a corrupt pixel fails its packet's CRC and the frame is not delivered", "[hal][flirone]") {
  auto frame = make_flirone_frame();
  frame[hal::flirone::kHeaderBytes + 17 * 164 + 40] ^= 0x01;
  FlirOneReassembler r;
  CHECK_FALSE(r.push_transfer(frame));
  CHECK(r.counters().bad_crc == 1);
  CHECK(r.counters().frames == 0);
  // The next good frame is delivered.
  CHECK(r.push_transfer(make_flirone_frame()));
  // Without CRC checks the same frame passes (cores whose CRCs are not computed).
  FlirOneReassembler lax(hal::flirone::kDefaultMaxFrameBytes, false);
  CHECK(lax.push_transfer(frame));
}

TEST_CASE("flirone: a packet with another row's id is refused even with a valid CRC", "[hal][flirone]") {
  auto frame = make_flirone_frame();
  test::put_le16(frame, hal::flirone::kHeaderBytes + 5 * 164, 6);
  test::fix_crc(frame, 5);
  FlirOneReassembler r;
  CHECK_FALSE(r.push_transfer(frame));
  CHECK(r.counters().bad_row_id == 1);
}

TEST_CASE("flirone: a frame cut short by the next magic is counted as truncated", "[hal][flirone]") {
  const auto frame = make_flirone_frame();
  FlirOneReassembler r;
  CHECK_FALSE(r.push_transfer({frame.data(), 5000}));
  CHECK(r.push_transfer(frame));  // restart on magic
  CHECK(r.counters().truncated == 1);
  CHECK(r.counters().frames == 1);
}

TEST_CASE("flirone: data without a frame start is stray, bytes after a frame are trailing", "[hal][flirone]") {
  const auto frame = make_flirone_frame();
  FlirOneReassembler r;
  CHECK_FALSE(r.push_transfer({frame.data() + 100, 500}));
  CHECK(r.counters().stray_transfers == 1);
  auto with_tail = frame;
  with_tail.insert(with_tail.end(), {1, 2, 3, 4, 5});
  CHECK(r.push_transfer(with_tail));
  CHECK(r.counters().trailing_bytes == 5);
  CHECK_FALSE(r.poll());
  CHECK(r.buffered() == 0);
}

TEST_CASE("flirone: a frame start after a frame's end in the same transfer is kept", "[hal][flirone]") {
  auto two = make_flirone_frame({.base = 1000});
  const auto second = make_flirone_frame({.base = 2000});
  two.insert(two.end(), second.begin(), second.end());
  FlirOneReassembler r;
  REQUIRE(r.push_transfer(two));
  CHECK(r.frame().pixels[0] == 1000);
  REQUIRE(r.poll());
  CHECK(r.frame().pixels[0] == 2000);
  CHECK_FALSE(r.poll());
  CHECK(r.counters().frames == 2);
}

TEST_CASE("flirone: inconsistent or oversized header lengths are refused", "[hal][flirone]") {
  FlirOneReassembler r(64 * 1024);
  auto frame = make_flirone_frame();
  SECTION("thermal length not 63 packets") { test::put_le32(frame, 12, 10000); }
  SECTION("parts do not add up to the total") { test::put_le32(frame, 20, 5); }
  SECTION("total over the buffer") {
    test::put_le32(frame, 16, 200000);
    test::put_le32(frame, 8, 10332 + 200000 + 114);
  }
  SECTION("parts overflow 32 bits") {
    test::put_le32(frame, 16, 0xFFFFFFF0u);
    test::put_le32(frame, 8, 10332 + 0x10u + 114);
  }
  CHECK_FALSE(r.push_transfer(frame));
  CHECK(r.counters().bad_header == 1);
  CHECK(r.buffered() == 0);
}

TEST_CASE("flirone: the JSON status is read field by field, a broken one leaves the frame good", "[hal][flirone]") {
  FlirOneReassembler r;
  SECTION("unreadable") {
    CHECK(r.push_transfer(make_flirone_frame({.json = R"({"shutterState":"ON)"})));
    CHECK_FALSE(r.frame().status_ok);
    CHECK(r.counters().bad_status == 1);
  }
  SECTION("unknown fields and spacing") {
    CHECK(r.push_transfer(make_flirone_frame(
        {.json = R"({ "a" : [1], "shutterState" : "OFF" })"})));  // nested values are refused
    CHECK_FALSE(r.frame().status_ok);
    CHECK(r.push_transfer(make_flirone_frame(
        {.json = R"({ "a" : true, "b":"x\"y", "shutterState" : "OFF", "shutterTemperature": -1.5 })"})));
    CHECK(r.frame().status_ok);
    CHECK(std::string(r.frame().status.shutter_state) == "OFF");
    CHECK(r.frame().status.shutter_temp_mk == -1500);
    CHECK_FALSE(r.frame().status.has_usb_timestamp);
  }
}

TEST_CASE("flirone: the thermal length picks the geometry, 80x60 or 160x120, from one table", "[hal][flirone]") {
  CHECK(hal::flirone::geometry_for(10332)->width == 80);
  CHECK(hal::flirone::geometry_for(40016)->height == 120);
  CHECK(hal::flirone::geometry_for(10333) == nullptr);

  hal::FlirOneReassembler r;
  const auto bytes = test::make_flirone_frame_160({.base = 500, .frame_counter = 77, .fpa_ck = 30100});
  REQUIRE(r.push_transfer(bytes));
  const hal::FlirOneFrame& f = r.frame();
  CHECK(f.geometry->width == 160);
  CHECK(f.pixels[0] == 500);
  CHECK(f.pixels[80] == 580);                  // the right half, after its own prefix
  CHECK(f.pixels[159 + 160 * 119] == 500 + 159 + 160 * 119);
  CHECK(f.lepton.frame_counter == 77);
  CHECK(f.lepton.fpa_temp_ck == 30100);
  CHECK(f.status_ok);
  CHECK(r.counters().bad_header == 0);
}
