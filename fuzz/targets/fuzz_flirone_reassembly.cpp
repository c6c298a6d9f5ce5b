// FLIR ONE Pro reassembly (bolo::hal::FlirOneReassembler) and the source above it
// (FlirOneSource) on arbitrary bulk transfers. Input: one flag byte (bit 0: verify CRCs, bit 1:
// skip duplicates, bits 2-3: buffer size), then the transfers, separated by "--xfer--".
// Properties: no crash; a push completes at most one frame and poll() the ones after it; every
// good frame's telemetry agrees with its raw rows and its JSON texts are terminated; the source
// delivers exactly the reassembler's good frames (less skipped duplicates), 60 lines each; the
// buffer never holds more than its size; every call of the JSON scanner stays inside its input.

#include <cstring>
#include <vector>

#include "bolo/hal/flirone_source.hpp"
#include "fuzz_support.hpp"
#include "pipeline_harness.hpp"

using namespace bolo;

namespace {

constexpr std::size_t kMaxTransfers = 64;

class Replay final : public hal::BulkInTransport {
 public:
  explicit Replay(std::span<const std::span<const std::uint8_t>> t) : transfers_(t) {}
  hal::Transfer next(std::span<std::uint8_t> buffer, std::uint32_t) override {
    hal::Transfer t;
    if (next_ >= transfers_.size()) {
      t.status = hal::TransferStatus::end;
      return t;
    }
    const auto bytes = transfers_[next_++];
    if (bytes.size() > buffer.size()) {
      t.status = hal::TransferStatus::error;
      return t;
    }
    if (!bytes.empty()) std::memcpy(buffer.data(), bytes.data(), bytes.size());
    t.bytes = bytes.size();
    return t;
  }
  bool reconnect(std::uint32_t) override { return false; }

 private:
  std::span<const std::span<const std::uint8_t>> transfers_;
  std::size_t next_ = 0;
};

void check_frame(const hal::FlirOneFrame& f) {
  BOLO_FUZZ_CHECK(f.lepton.frame_counter == (f.telemetry[0][20] | (std::uint32_t{f.telemetry[0][21]} << 16)));
  BOLO_FUZZ_CHECK(f.lepton.fpa_temp_ck == f.telemetry[0][24]);
  BOLO_FUZZ_CHECK(std::strlen(f.status.shutter_state) < hal::FlirOneStatus::kTextCapacity);
  BOLO_FUZZ_CHECK(std::strlen(f.status.ffc_state) < hal::FlirOneStatus::kTextCapacity);
  BOLO_FUZZ_CHECK(f.jpeg.size() == f.jpeg_bytes);
  BOLO_FUZZ_CHECK(std::uint64_t{f.jpeg_bytes} + f.json_bytes + hal::flirone::kThermalBytes == f.total_bytes);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  const std::uint8_t flags = in.u8();
  const bool verify_crc = (flags & 1) != 0, skip_duplicates = (flags & 2) != 0;
  const std::size_t max_frame = std::size_t{16 * 1024} << ((flags >> 2) & 3);  // 16..128 KiB
  std::span<const std::uint8_t> parts[kMaxTransfers];
  const std::size_t n = fuzz::split(in.rest(), "--xfer--", parts);

  hal::FlirOneReassembler r(max_frame, verify_crc);
  std::uint64_t completed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t before = r.counters().frames;
    if (r.push_transfer(parts[i])) {
      ++completed;
      check_frame(r.frame());
    }
    BOLO_FUZZ_CHECK(r.counters().frames - before <= 1);
    for (int polls = 0; r.poll(); ++polls) {
      BOLO_FUZZ_CHECK(polls < 64);
      ++completed;
      check_frame(r.frame());
    }
    BOLO_FUZZ_CHECK(r.buffered() <= (max_frame < 10360 ? 10360 : max_frame));
    // The JSON scanner on raw bytes: bounded by its input whatever they are.
    hal::FlirOneStatus status;
    hal::parse_flirone_status(parts[i], status);
  }
  BOLO_FUZZ_CHECK(completed == r.counters().frames);

  Replay usb(std::span<const std::span<const std::uint8_t>>(parts, n));
  hal::FlirOneSource source(usb, {.verify_crc = verify_crc, .skip_duplicates = skip_duplicates,
                                  .max_frame_bytes = max_frame});
  fuzz::CheckingSink sink(hal::flirone::kWidth);
  sink.lines_in = hal::flirone::kHeight;
  std::uint64_t frames = 0;
  for (std::size_t calls = 0;; ++calls) {
    BOLO_FUZZ_CHECK(calls <= 8 * n + 2);  // a transfer can end several small frames
    const hal::StreamStatus s = source.stream_frame(sink);
    if (s == hal::StreamStatus::end_of_stream) break;
    if (s == hal::StreamStatus::frame) ++frames;
  }
  const hal::SourceStats st = source.stats();
  BOLO_FUZZ_CHECK(st.frames_delivered == frames);
  BOLO_FUZZ_CHECK(sink.frames_begun == frames && sink.frames_ended == frames);
  BOLO_FUZZ_CHECK(frames + (skip_duplicates ? st.duplicates : 0) == source.reassembler().counters().frames);
  return 0;
}
