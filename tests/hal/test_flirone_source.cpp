// FlirOneSource over a scripted transport: timeouts, failed transfers, corrupt frames and an
// unplug/replug are counted, never crash, leave a sequence gap, and streaming goes on.

#include <catch2/catch.hpp>

#include <deque>

#include "../firmware/frame_collector.hpp"
#include "bolo/firmware/two_frame_corrector.hpp"
#include "bolo/hal/flirone_source.hpp"
#include "flirone_frames.hpp"

using namespace bolo;

namespace {

// Replays a script of transfers and transport events.
class ScriptedTransport final : public hal::BulkInTransport {
 public:
  struct Step {
    hal::TransferStatus status = hal::TransferStatus::ok;
    std::vector<std::uint8_t> bytes;
  };
  void frame(const std::vector<std::uint8_t>& bytes, std::size_t chunk = 16384) {
    std::vector<std::vector<std::uint8_t>> parts;
    test::split_into_transfers(bytes, chunk, parts);
    for (auto& p : parts) steps.push_back({hal::TransferStatus::ok, std::move(p)});
  }
  void event(hal::TransferStatus s) { steps.push_back({s, {}}); }

  hal::Transfer next(std::span<std::uint8_t> buffer, std::uint32_t) override {
    hal::Transfer t;
    if (steps.empty()) {
      t.status = hal::TransferStatus::end;
      return t;
    }
    Step s = std::move(steps.front());
    steps.pop_front();
    t.status = s.status;
    t.bytes = s.bytes.size();
    t.arrival_ns = ++clock * 1000;
    std::copy(s.bytes.begin(), s.bytes.end(), buffer.begin());
    return t;
  }
  bool reconnect(std::uint32_t) override {
    ++reconnects;
    return replug;
  }
  std::deque<Step> steps;
  std::int64_t clock = 0;
  int reconnects = 0;
  bool replug = true;
};

std::vector<hal::StreamStatus> run(hal::FlirOneSource& source, test::HashingCollector& sink,
                                   std::vector<std::uint64_t>& sequences) {
  std::vector<hal::StreamStatus> out;
  for (hal::StreamStatus s; (s = source.stream_frame(sink)) != hal::StreamStatus::end_of_stream;) {
    out.push_back(s);
    if (s == hal::StreamStatus::frame) sequences.push_back(sink.header().sequence);
    REQUIRE(out.size() < 100);
  }
  return out;
}

}  // namespace

TEST_CASE("flirone source: faults are counted, lost frames leave sequence gaps", "[hal][flirone]") {
  using S = hal::StreamStatus;
  using T = hal::TransferStatus;
  ScriptedTransport usb;
  usb.frame(test::make_flirone_frame({.frame_counter = 3}));            // seq 0
  usb.event(T::timeout);                                                 // nothing lost mid-frame
  auto bad = test::make_flirone_frame({.frame_counter = 6});
  bad[5000] ^= 0x80;
  usb.frame(bad);                                                        // seq 1 lost: CRC
  usb.frame(test::make_flirone_frame({.frame_counter = 9}));            // seq 2
  auto part = test::make_flirone_frame({.frame_counter = 12});
  part.resize(5000);
  usb.frame(part);
  usb.event(T::error);                                                   // seq 3 lost mid-frame
  usb.frame(test::make_flirone_frame({.frame_counter = 15}));           // seq 4
  usb.frame(std::vector<std::uint8_t>(part.begin(), part.begin() + 4000));
  usb.event(T::disconnected);                                            // unplug, replug
  usb.frame(test::make_flirone_frame({.frame_counter = 1, .last_ffc_ms = 9000}));  // seq 5
  usb.frame(test::make_flirone_frame({.frame_counter = 4, .last_ffc_ms = 9500}));  // seq 6: FFC

  hal::FlirOneSource source(usb, {.clock = hal::FlirOneClock::host});
  test::HashingCollector sink(80, 60);
  std::vector<std::uint64_t> seq;
  const auto statuses = run(source, sink, seq);
  CHECK(statuses == std::vector<S>{S::frame, S::fault, S::fault, S::frame, S::fault, S::frame,
                                   S::fault, S::frame, S::frame});
  CHECK(seq == std::vector<std::uint64_t>{0, 2, 4, 6, 7});
  const hal::SourceStats st = source.stats();
  CHECK(st.frames_delivered == 5);
  CHECK(st.timeouts == 1);
  CHECK(st.corrupt_transfers == 2);  // the CRC failure and the failed transfer
  CHECK(st.disconnects == 1);
  CHECK(st.reconnects == 1);
  CHECK(usb.reconnects == 1);
  CHECK(sink.header().ffc == fw::FfcState::completed);  // last-FFC time moved
  CHECK(sink.header().timestamp_valid);
  CHECK(sink.header().fpa_temp_mc == 46850);
  // The frames missing from the counter were lost on the wire (counted above), not in the
  // camera; the core counting from 1 after the replug is a new start, not a jump.
  CHECK(source.skipped_in_camera() == 0);
  CHECK(source.counter_jumps() == 0);
}

TEST_CASE("flirone source: the telemetry counter shows frames skipped in the camera and jumps", "[hal][flirone]") {
  ScriptedTransport usb;
  // The core counts 3 per exported frame. 12 (9 skipped), 15 twice, 24 after a frame lost on the
  // wire (21; 18 skipped), then a jump by 100 frames and on from there.
  for (std::uint32_t counter : {3u, 6u, 12u, 15u, 15u}) usb.frame(test::make_flirone_frame({.frame_counter = counter}));
  auto bad = test::make_flirone_frame({.frame_counter = 21});
  bad[5000] ^= 0x80;
  usb.frame(bad);
  for (std::uint32_t counter : {24u, 324u, 327u}) usb.frame(test::make_flirone_frame({.frame_counter = counter}));
  hal::FlirOneSource source(usb);
  test::HashingCollector sink(80, 60);
  std::vector<std::uint64_t> seq;
  run(source, sink, seq);
  // Every missing frame leaves a gap: 12 comes 2 after 6 (9 skipped), 24 comes 3 after the
  // second 15 (21 lost on the wire, 18 skipped). A repeat and a jump leave none.
  CHECK(seq == std::vector<std::uint64_t>{0, 1, 3, 4, 5, 8, 9, 10});
  CHECK(source.skipped_in_camera() == 2);  // 9 and 18
  CHECK(source.counter_jumps() == 1);
  CHECK(source.stats().duplicates == 1);
  CHECK(source.stats().corrupt_transfers == 1);
  const hal::ExtraCounters extra = source.extra_counters();
  CHECK(extra.find("skipped_in_camera")->value == 2);
  CHECK(extra.find("counter_jumps")->value == 1);
}

TEST_CASE("flirone source: a skipped duplicate still counts, and a skip after it", "[hal][flirone]") {
  ScriptedTransport usb;
  for (std::uint32_t counter : {3u, 6u, 6u, 12u}) usb.frame(test::make_flirone_frame({.frame_counter = counter}));
  hal::FlirOneSource source(usb, {.skip_duplicates = true});
  test::HashingCollector sink(80, 60);
  std::vector<std::uint64_t> seq;
  run(source, sink, seq);
  CHECK(seq == std::vector<std::uint64_t>{0, 1, 3});  // the skipped 9 is a gap, the skipped duplicate none
  CHECK(source.stats().duplicates == 1);
  CHECK(source.skipped_in_camera() == 1);
}

TEST_CASE("flirone source: the frame after frames the camera skipped is not corrected against the one before", "[hal][flirone]") {
  // The core counts 3 per exported frame; it never sent 9. Arrival times stay evenly spaced (as
  // from a host that polls), so only the sequence can tell the corrector 12 has no predecessor.
  ScriptedTransport usb;
  for (std::uint32_t counter : {3u, 6u, 12u, 15u}) usb.frame(test::make_flirone_frame({.frame_counter = counter}));
  hal::FlirOneSource source(usb, {.clock = hal::FlirOneClock::host});
  test::HashingCollector out(80, 60);
  fw::CorrectorConfig config;
  config.width = 80;
  config.height = 60;
  config.tau = {12'000'000, 12'000'000};
  config.default_exposure_ns = 10'000'000;
  config.default_readout_ns = 6'000'000;
  std::vector<fw::Pixel> storage(fw::TwoFrameCorrector::storage_pixels(80, 60));
  fw::TwoFrameCorrector corrector(config, storage, out);
  std::vector<std::uint64_t> seq;
  std::vector<fw::CarryOver> carry_over;
  while (source.stream_frame(corrector) == hal::StreamStatus::frame) {
    seq.push_back(out.header().sequence);
    carry_over.push_back(corrector.last_frame().carry_over);
  }
  CHECK(seq == std::vector<std::uint64_t>{0, 1, 3, 4});  // one frame skipped: a step of 2
  CHECK(carry_over == std::vector<fw::CarryOver>{fw::CarryOver::first_frame, fw::CarryOver::applied,
                                                 fw::CarryOver::sequence_gap, fw::CarryOver::applied});
  CHECK(source.skipped_in_camera() == 1);
}

TEST_CASE("flirone source: a pause mid-frame is a counted timeout, not a lost frame", "[hal][flirone]") {
  using S = hal::StreamStatus;
  using T = hal::TransferStatus;
  ScriptedTransport usb;
  const auto whole = test::make_flirone_frame({.frame_counter = 3});
  usb.frame(std::vector<std::uint8_t>(whole.begin(), whole.begin() + 5000));
  usb.event(T::timeout);  // the device (or a loaded host) stalls, then goes on with the frame
  usb.frame(std::vector<std::uint8_t>(whole.begin() + 5000, whole.end()));
  // A pause after which the device starts the next frame: the first is cut short.
  const auto cut = test::make_flirone_frame({.frame_counter = 6});
  usb.frame(std::vector<std::uint8_t>(cut.begin(), cut.begin() + 5000));
  usb.event(T::timeout);
  usb.frame(test::make_flirone_frame({.frame_counter = 9}));
  hal::FlirOneSource source(usb, {.clock = hal::FlirOneClock::host});
  test::HashingCollector sink(80, 60);
  std::vector<std::uint64_t> seq;
  const auto statuses = run(source, sink, seq);
  CHECK(statuses == std::vector<S>{S::fault, S::frame, S::fault, S::frame});
  CHECK(seq == std::vector<std::uint64_t>{0, 2});  // the cut frame leaves its gap
  CHECK(source.stats().timeouts == 2);
  CHECK(source.stats().frames_delivered == 2);
  CHECK(source.stats().short_transfers == 1);
}

TEST_CASE("flirone source: the first frame after a replug is not an FFC, a new FFC stamp is", "[hal][flirone]") {
  ScriptedTransport usb;
  usb.frame(test::make_flirone_frame({.frame_counter = 3, .last_ffc_ms = 1}));
  usb.frame(test::make_flirone_frame({.frame_counter = 6, .last_ffc_ms = 1}));
  usb.frame(test::make_flirone_frame({.frame_counter = 9, .last_ffc_ms = 2}));
  hal::FlirOneSource source(usb);
  test::HashingCollector sink(80, 60);
  std::vector<fw::FfcState> ffc;
  while (source.stream_frame(sink) == hal::StreamStatus::frame) ffc.push_back(sink.header().ffc);
  CHECK(ffc == std::vector<fw::FfcState>{fw::FfcState::none, fw::FfcState::none, fw::FfcState::completed});
  // Camera clock: the JSON's usbNotifiedTimestamp.
  CHECK(sink.header().timestamp_ns == 100'250'000'000);
}

TEST_CASE("flirone source: a device that stays away keeps reporting faults, never a frame", "[hal][flirone]") {
  ScriptedTransport usb;
  usb.replug = false;
  for (int i = 0; i < 3; ++i) usb.event(hal::TransferStatus::disconnected);
  hal::FlirOneSource source(usb);
  test::HashingCollector sink(80, 60);
  std::vector<std::uint64_t> seq;
  const auto statuses = run(source, sink, seq);
  CHECK(statuses.size() == 3);
  CHECK(source.stats().disconnects == 1);  // one unplug, however many attempts to get it back
  CHECK(usb.reconnects == 3);
  CHECK(source.stats().reconnects == 0);
  CHECK(sink.frames() == 0);
}

TEST_CASE("flirone source: stray transfers, trailing bytes and unread statuses are extra counters", "[hal][flirone]") {
  ScriptedTransport usb;
  usb.steps.push_back({hal::TransferStatus::ok, {1, 2, 3, 4}});  // joined mid-frame: stray
  usb.frame(test::make_flirone_frame({.frame_counter = 3, .json = R"({"shutterState":"ON)"}));
  auto with_tail = test::make_flirone_frame({.frame_counter = 6});
  with_tail.insert(with_tail.end(), {9, 9, 9});  // after the frame's end, not a frame's start
  usb.steps.push_back({hal::TransferStatus::ok, with_tail});
  hal::FlirOneSource source(usb);
  test::HashingCollector sink(80, 60);
  std::vector<std::uint64_t> seq;
  run(source, sink, seq);
  CHECK(seq.size() == 2);  // none of them costs a frame
  const hal::ExtraCounters extra = source.extra_counters();
  REQUIRE(extra.find("stray_transfers") != nullptr);
  CHECK(extra.items()[0].name == "skipped_in_camera");
  CHECK(extra.items()[1].name == "counter_jumps");
  CHECK(extra.find("stray_transfers")->value == 1);
  CHECK(extra.find("trailing_bytes")->value == 3);
  CHECK(extra.find("bad_status")->value == 1);
}

TEST_CASE("flirone source: a 160x120 core's frames come out 160x120, format and header alike", "[hal][flirone]") {
  ScriptedTransport usb;
  usb.frame(test::make_flirone_frame_160({.base = 1000, .frame_counter = 3}), 30000);
  usb.frame(test::make_flirone_frame_160({.base = 2000, .frame_counter = 6}), 30000);
  usb.frame(test::make_flirone_frame({.frame_counter = 9}));  // an 80x60 frame in a 160x120 stream
  usb.frame(test::make_flirone_frame_160({.base = 3000, .frame_counter = 12}), 30000);

  hal::FlirOneSource source(usb);
  REQUIRE(source.probe());
  CHECK(source.format().width == 160);
  CHECK(source.format().height == 120);

  test::HashingCollector sink(160, 120);
  std::vector<std::uint64_t> seq;
  std::vector<std::vector<fw::Pixel>> frames;
  using S = hal::StreamStatus;
  std::vector<S> statuses;
  for (S s; (s = source.stream_frame(sink)) != S::end_of_stream;) {
    statuses.push_back(s);
    if (s != S::frame) continue;
    CHECK(sink.header().width == 160);
    CHECK(sink.header().height == 120);
    frames.push_back(sink.frame());
  }
  CHECK(statuses == std::vector<S>{S::frame, S::frame, S::fault, S::frame});
  REQUIRE(frames.size() == 3);
  for (std::uint32_t y : {0u, 57u, 119u})
    for (std::uint32_t x : {0u, 79u, 80u, 159u})
      CHECK(frames[1][y * 160 + x] == 2000 + x + 160 * y);
  CHECK(source.last_frame().lepton.frame_counter == 12);
  CHECK(source.stats().corrupt_transfers == 1);
  CHECK(source.stats().frames_delivered == 3);

  // Without probe(), a format handed out before the first frame (80x60) holds for the stream.
  ScriptedTransport later;
  later.frame(test::make_flirone_frame_160({}), 30000);
  hal::FlirOneSource unprobed(later);
  CHECK(unprobed.format().width == 80);
  CHECK(unprobed.stream_frame(sink) == S::fault);
  CHECK(unprobed.stats().corrupt_transfers == 1);
}
