// The real FLIR ONE Pro capture (../shared/data/usb/flirone-pro, 109 bulk transfers) through
// the same source code that runs on libusb, compared with the recording made from the same
// capture (../shared/data/real/flirone-lepton-telemetry): every frame bit for bit, its
// temperatures and its time stamps.

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "../firmware/frame_collector.hpp"
#include "../test_support.hpp"
#include "bolo/hal/captured_transfers.hpp"
#include "bolo/hal/flirone_source.hpp"
#include "bolo/recording/recording.hpp"

using namespace bolo;
namespace fs = std::filesystem;

namespace {

// Empty (the case skipped) when ../shared/data is absent.
fs::path capture_dir() { return test::shared_folder("usb/flirone-pro", "1.txt"); }

}  // namespace

TEST_CASE("flirone capture: 20 frames, every packet's CRC verifies, telemetry and JSON read", "[hal][flirone][real]") {
  const fs::path dir = capture_dir();
  if (dir.empty()) return;
  hal::CapturedTransfers log(dir);
  REQUIRE(log.transfers().size() == 109);
  hal::FlirOneReassembler r;  // CRC checks on
  std::uint32_t counters[20] = {};
  std::size_t frames = 0;
  for (const auto& t : log.transfers()) {
    if (r.push_transfer(t)) {
      REQUIRE(frames < 20);
      const hal::FlirOneFrame& f = r.frame();
      counters[frames++] = f.lepton.frame_counter;
      CHECK(f.status_ok);
      CHECK(std::string(f.status.shutter_state) == "ON");
      CHECK(std::string(f.status.ffc_state) == "FFC_VALID_RAD");
      CHECK(f.lepton.ffc_state == hal::LeptonFfcState::complete);
      CHECK(f.jpeg.size() > 2);
      CHECK(f.jpeg[0] == 0xFF);  // a JPEG's SOI marker
      CHECK(f.jpeg[1] == 0xD8);
    }
    CHECK_FALSE(r.poll());
  }
  CHECK(frames == 20);
  const hal::FlirOneCounters& c = r.counters();
  CHECK(c.frames == 20);  // 20 x 63 = 1260 packets, all CRCs verified
  CHECK(c.bad_crc == 0);
  CHECK(c.bad_row_id == 0);
  CHECK(c.truncated == 0);
  CHECK(c.bad_header == 0);
  CHECK(c.stray_transfers == 0);
  CHECK(c.trailing_bytes == 0);
  CHECK(c.bad_status == 0);
  // The core runs at ~27 Hz and exports every third frame; two frames were exported twice.
  CHECK(counters[0] == 147678);
  CHECK(counters[1] == counters[0]);
  CHECK(counters[2] == counters[0] + 3);
  CHECK(counters[11] == counters[10]);
  CHECK(counters[19] == 147729);
}

TEST_CASE("flirone capture: the source's frames equal the shared recording bit for bit", "[hal][flirone][real]") {
  const fs::path dir = capture_dir();
  if (dir.empty()) return;
  const fs::path rec_dir = test::shared_recording("flirone-lepton-telemetry");
  rec::Recording recording(rec_dir);
  REQUIRE(recording.frame_count() == 20);
  hal::CapturedTransfers log(dir);
  hal::FlirOneSource source(log);
  CHECK(source.format().width == 80);
  CHECK(source.format().height == 60);
  test::HashingCollector sink(80, 60);
  std::vector<std::uint16_t> expected(80 * 60);
  std::int64_t t0 = 0;
  std::uint64_t n = 0;
  for (hal::StreamStatus s; (s = source.stream_frame(sink)) != hal::StreamStatus::end_of_stream;) {
    REQUIRE(s == hal::StreamStatus::frame);
    REQUIRE(n < 20);
    INFO("frame " << n);
    recording.read_frame(n, expected);
    CHECK(sink.frame() == expected);
    CHECK(sink.lines() == 60);
    const fw::FrameHeader& h = sink.header();
    const rec::FrameRow& row = recording.rows()[n];
    CHECK(h.sequence == n);
    CHECK(h.fpa_temp_mc == std::lround(*row.fpa_temp_c * 1000));
    CHECK(h.housing_temp_mc == std::lround(*row.housing_temp_c * 1000));
    CHECK(h.ffc == fw::FfcState::none);
    REQUIRE(h.timestamp_valid);
    if (n == 0) t0 = h.timestamp_ns;
    // The recording's t_s are the JSON's usbNotifiedTimestamp relative to the first frame (µs).
    CHECK(std::abs(static_cast<double>(h.timestamp_ns - t0) * 1e-9 - *row.t_s) < 1e-6);
    ++n;
  }
  CHECK(n == 20);
  const hal::SourceStats stats = source.stats();
  CHECK(stats.frames_delivered == 20);
  CHECK(stats.duplicates == 2);
  CHECK(stats.short_transfers + stats.corrupt_transfers + stats.timeouts + stats.disconnects == 0);
  // The counter steps by 3 from 147678 to 147729: 17 steps and the 2 repeats, nothing skipped.
  CHECK(source.skipped_in_camera() == 0);
  CHECK(source.counter_jumps() == 0);
}

TEST_CASE("flirone capture: duplicates can be skipped", "[hal][flirone][real]") {
  const fs::path dir = capture_dir();
  if (dir.empty()) return;
  hal::CapturedTransfers log(dir);
  hal::FlirOneSource source(log, {.skip_duplicates = true});
  test::HashingCollector sink(80, 60);
  std::uint64_t n = 0;
  while (source.stream_frame(sink) == hal::StreamStatus::frame) ++n;
  CHECK(n == 18);
  CHECK(source.stats().duplicates == 2);
}
