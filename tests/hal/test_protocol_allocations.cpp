// The device protocol layers and the sources over them allocate nothing after construction
// (they run on camera boards): malloc and operator new are counted in this binary while FLIR ONE
// transfers (good, corrupt, truncated), Seek frames and Y16 frames stream through them.

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <vector>

#include "../firmware/frame_collector.hpp"
#include "bolo/hal/flirone_source.hpp"
#include "bolo/hal/seek_source.hpp"
#include "bolo/hal/y16_frame.hpp"
#include "flirone_frames.hpp"
#include "seek_device.hpp"

#include "counting_allocator.hpp"  // replaces malloc/new in this binary

using bolo::test::g_allocations;
using bolo::test::g_counting;

namespace {

using namespace bolo;

// Transfers prepared up front, served round and round; every 7th is reported as a timeout.
class Prepared final : public hal::BulkInTransport {
 public:
  explicit Prepared(const std::vector<std::vector<std::uint8_t>>& t) : t_(t) {}
  hal::Transfer next(std::span<std::uint8_t> buffer, std::uint32_t) override {
    hal::Transfer out;
    if (++calls_ % 7 == 0) {
      out.status = hal::TransferStatus::timeout;
      return out;
    }
    const auto& bytes = t_[i_++ % t_.size()];
    std::memcpy(buffer.data(), bytes.data(), bytes.size());
    out.bytes = bytes.size();
    return out;
  }
  bool reconnect(std::uint32_t) override { return true; }

 private:
  const std::vector<std::vector<std::uint8_t>>& t_;
  std::size_t i_ = 0, calls_ = 0;
};

// A Seek that answers every frame request with the next prepared frame, in chunks.
class PreparedSeek final : public hal::VendorUsbTransport {
 public:
  PreparedSeek(const hal::SeekModel& m, const std::vector<std::vector<std::uint8_t>>& frames)
      : m_(m), frames_(frames) {}
  hal::Transfer control_out(std::uint8_t request, std::span<const std::uint8_t> d) override {
    if (request == hal::seek::kStartGetImageTransfer) {
      current_ = &frames_[f_++ % frames_.size()];
      at_ = 0;
    }
    return {hal::TransferStatus::ok, d.size(), 0};
  }
  hal::Transfer control_in(std::uint8_t, std::span<std::uint8_t> d) override {
    return {hal::TransferStatus::ok, d.size(), 0};
  }
  hal::Transfer next(std::span<std::uint8_t> buffer, std::uint32_t) override {
    const std::size_t n = std::min<std::size_t>(m_.chunk_bytes, current_->size() - at_);
    std::memcpy(buffer.data(), current_->data() + at_, n);
    at_ += n;
    return {hal::TransferStatus::ok, n, 1};
  }
  bool reconnect(std::uint32_t) override { return true; }

 private:
  hal::SeekModel m_;
  const std::vector<std::vector<std::uint8_t>>& frames_;
  const std::vector<std::uint8_t>* current_ = nullptr;
  std::size_t f_ = 0, at_ = 0;
};

int failures = 0;
void expect(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what);
    ++failures;
  }
}

}  // namespace

int main() {
  if (!BOLO_COUNTING_ALLOCATOR_ACTIVE) {
    std::printf("SKIPPED: a sanitizer owns malloc in this build; heap allocations cannot be counted\n");
    return bolo::test::kSkipExitCode;
  }
  // FLIR ONE: good frames in 16 KiB transfers, a corrupt one, a truncated one.
  std::vector<std::vector<std::uint8_t>> transfers;
  for (std::uint32_t i = 0; i < 4; ++i) {
    auto f = test::make_flirone_frame({.frame_counter = 3 * i, .jpeg_bytes = 30000});
    if (i == 2) f[4000] ^= 1;
    if (i == 3) f.resize(20000);
    test::split_into_transfers(f, 16384, transfers);
  }
  Prepared usb(transfers);
  hal::FlirOneSource flirone(usb);
  test::HashingCollector flirone_sink(80, 60);

  // Seek: start-up frame, shutter, images.
  std::vector<std::vector<std::uint8_t>> seek_frames;
  for (std::uint16_t type : {4, 6, 1, 20, 3, 3, 3})
    seek_frames.push_back(test::make_seek_frame(hal::kSeekCompact, type, 1, 0, {5, 9}));
  PreparedSeek seek_usb(hal::kSeekCompact, seek_frames);
  hal::SeekSource seek(seek_usb, hal::kSeekCompact);
  test::HashingCollector seek_sink(207, 154);

  // Y16 with telemetry.
  std::vector<std::uint8_t> y16(160 * 122 * 2, 0x11);
  const hal::Y16Layout layout{160, 120, 2, 0};
  std::vector<std::uint16_t> row(160);

  g_counting = true;
  std::uint64_t flirone_frames = 0, seek_images = 0;
  for (int i = 0; i < 400; ++i)
    if (flirone.stream_frame(flirone_sink) == hal::StreamStatus::frame) ++flirone_frames;
  for (int i = 0; i < 200; ++i)
    if (seek.stream_frame(seek_sink) == hal::StreamStatus::frame) ++seek_images;
  hal::LeptonTelemetry t;
  for (int i = 0; i < 200; ++i) {
    if (hal::Y16Frame::check(y16, layout) != hal::Y16Check::ok) break;
    const hal::Y16Frame frame(y16, layout);
    for (std::uint32_t r = 0; r < 120; ++r) frame.image_row(r, row);
    frame.telemetry(t);
  }
  g_counting = false;

  const hal::SourceStats fs = flirone.stats();
  std::printf("flirone: %llu frames, %llu corrupt, %llu short, %llu timeouts; seek: %llu images; allocations %ld\n",
              static_cast<unsigned long long>(flirone_frames), static_cast<unsigned long long>(fs.corrupt_transfers),
              static_cast<unsigned long long>(fs.short_transfers), static_cast<unsigned long long>(fs.timeouts),
              static_cast<unsigned long long>(seek_images), g_allocations.load());
  expect(flirone_frames > 50, "FLIR ONE frames streamed");
  expect(fs.corrupt_transfers > 0 && fs.short_transfers > 0 && fs.timeouts > 0, "FLIR ONE faults exercised");
  expect(seek_images > 50, "Seek images streamed");
  expect(seek.counters().shutter_frames > 0, "Seek shutter frames seen");
  expect(g_allocations.load() == 0, "no allocation while streaming");
  // The counter itself works: one deliberate allocation is seen.
  g_counting = true;
  delete new std::vector<int>(3);
  g_counting = false;
  expect(g_allocations.load() == 2, "the counting allocator counts (vector object + its buffer)");
  return failures == 0 ? 0 : 1;
}
