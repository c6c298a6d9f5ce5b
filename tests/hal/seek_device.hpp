#pragma once
// A Seek camera on the far side of VendorUsbTransport, answering as usb-thermal-cores.md says:
// control requests logged, a frame request queues one frame of the next scripted type cut into
// bulk chunks. Scripted faults replace a chunk (zero-length read, timeout, error, unplug) or hold
// it back (pause: `pause_timeouts` silent reads, then the frame goes on).

#include <cstdint>
#include <deque>
#include <vector>

#include "bolo/hal/seek_source.hpp"

namespace bolo::test {

// A raw Seek frame: type and counter in their words, pixel i = base + i % 1000 elsewhere, with
// `dead` positions (image pixel indices) set to 0x0000 / 0xFFFF alternately.
inline std::vector<std::uint8_t> make_seek_frame(const hal::SeekModel& m, std::uint16_t type,
                                                 std::uint16_t counter, std::uint16_t base = 2000,
                                                 const std::vector<std::uint32_t>& dead = {}) {
  std::vector<std::uint16_t> w(m.pixels());
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = static_cast<std::uint16_t>(base + i % 1000);
  for (std::size_t k = 0; k < dead.size(); ++k)
    w[std::size_t{m.header_rows} * m.width + dead[k]] = k % 2 ? 0xFFFF : 0x0000;
  w[m.type_word] = type;
  w[m.counter_word] = counter;
  std::vector<std::uint8_t> b(w.size() * 2);
  for (std::size_t i = 0; i < w.size(); ++i) {
    b[2 * i] = static_cast<std::uint8_t>(w[i] & 0xFF);
    b[2 * i + 1] = static_cast<std::uint8_t>(w[i] >> 8);
  }
  return b;
}

class FakeSeek final : public hal::VendorUsbTransport {
 public:
  // timeout: the camera abandons the frame (silent until asked again); pause: it goes on later.
  enum class Fault { none, zero_length, timeout, error, unplug, pause, silent };
  struct Planned {
    std::uint16_t type;
    Fault fault = Fault::none;  // replaces (pause: delays) the frame's second chunk
    std::uint16_t counter_step = 1;  // 0: the previous frame's counter again; > 1: a gap
  };
  explicit FakeSeek(const hal::SeekModel& m) : model(m) {}

  hal::Transfer control_out(std::uint8_t request, std::span<const std::uint8_t> data) override {
    log.push_back(request);
    hal::Transfer t;
    if (unplugged) {
      t.status = hal::TransferStatus::disconnected;
      return t;
    }
    if (fail_first_write && request == hal::seek::kTargetPlatform) {
      fail_first_write = false;
      t.status = hal::TransferStatus::error;
      return t;
    }
    if (request == hal::seek::kStartGetImageTransfer) {
      const std::uint32_t pixels = data[0] | data[1] << 8 | data[2] << 16 | std::uint32_t{data[3]} << 24;
      requested_pixels = pixels;
      if (unanswered_requests > 0)
        --unanswered_requests;  // not ready: the request is accepted and nothing is sent
      else
        queue_next_frame();
    }
    t.bytes = data.size();
    return t;
  }
  hal::Transfer control_in(std::uint8_t request, std::span<std::uint8_t> data) override {
    log.push_back(request);
    for (auto& b : data) b = 0xA5;
    return {unplugged ? hal::TransferStatus::disconnected : hal::TransferStatus::ok, data.size(), 0};
  }
  hal::Transfer next(std::span<std::uint8_t> buffer, std::uint32_t) override {
    hal::Transfer t;
    if (unplugged) {
      t.status = hal::TransferStatus::disconnected;
      return t;
    }
    if (chunks.empty()) {
      t.status = hal::TransferStatus::timeout;  // nothing requested: a real device stays silent
      return t;
    }
    auto [fault, bytes] = std::move(chunks.front());
    chunks.pop_front();
    switch (fault) {
      case Fault::none: break;
      case Fault::zero_length: bytes.clear(); chunks.clear(); break;
      case Fault::timeout: t.status = hal::TransferStatus::timeout; chunks.clear(); return t;
      case Fault::silent: t.status = hal::TransferStatus::timeout; return t;  // the rest still comes
      case Fault::pause: break;  // expanded into silent reads when queued
      case Fault::error: t.status = hal::TransferStatus::error; chunks.clear(); return t;
      case Fault::unplug: unplugged = true; chunks.clear(); t.status = hal::TransferStatus::disconnected; return t;
    }
    std::copy(bytes.begin(), bytes.end(), buffer.begin());
    t.bytes = bytes.size();
    t.arrival_ns = ++clock * 1'000'000;
    return t;
  }
  bool reconnect(std::uint32_t) override {
    ++reconnects;
    if (!replug) return false;
    unplugged = false;
    return true;
  }

  hal::SeekModel model;
  std::deque<Planned> plan;  // one entry per requested frame; type 3 when empty
  std::deque<std::pair<Fault, std::vector<std::uint8_t>>> chunks;
  std::vector<std::uint8_t> log;
  std::vector<std::uint32_t> dead_in_startup;
  std::uint32_t pause_timeouts = 1;  // silent reads of a pause
  std::uint32_t unanswered_requests = 0;  // the first this many frame requests get no frame
  std::uint32_t requested_pixels = 0;
  std::uint16_t counter = 0;
  std::int64_t clock = 0;
  int reconnects = 0;
  bool unplugged = false, replug = true, fail_first_write = false;

 private:
  void queue_next_frame() {
    Planned p{3};
    if (!plan.empty()) {
      p = plan.front();
      plan.pop_front();
    }
    counter = static_cast<std::uint16_t>(counter + p.counter_step);
    const auto frame = make_seek_frame(model, p.type, counter, static_cast<std::uint16_t>(1000 + counter),
                                       p.type == 4 ? dead_in_startup : std::vector<std::uint32_t>{});
    for (std::size_t at = 0, n = 0; at < frame.size(); at += model.chunk_bytes, ++n) {
      const std::size_t end = std::min(frame.size(), at + model.chunk_bytes);
      const bool paused = n == 1 && p.fault == Fault::pause;
      for (std::uint32_t k = 0; paused && k < pause_timeouts; ++k) chunks.emplace_back(Fault::silent, std::vector<std::uint8_t>{});
      chunks.emplace_back(n == 1 && !paused ? p.fault : Fault::none,
                          std::vector<std::uint8_t>(frame.begin() + static_cast<std::ptrdiff_t>(at),
                                                    frame.begin() + static_cast<std::ptrdiff_t>(end)));
    }
  }
};

}  // namespace bolo::test
