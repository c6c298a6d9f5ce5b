#pragma once
// A Seek camera on the far side of VendorUsbTransport, answering as usb-thermal-cores.md says.
// It demands the public driver's start-up sequence, from its own list (written here apart from
// the source's table, so that a wrong source is caught): a request out of order or with a wrong
// payload is refused (an error, as a stall looks) and counted in `refused`. Once the sequence is
// through, the camera boots: each frame request is answered with the next of `boot` (start-up
// frame first, then a shutter cycle), then of `plan` (type 3 when empty), cut into bulk chunks.
// Scripted faults replace a chunk (zero-length read, timeout, error, unplug) or hold it back
// (pause: `pause_timeouts` silent reads, then the frame goes on). Every frame queued is kept in
// `sent` (its words), for tests that compute the expected images themselves.
//
// Pixels: a per-pixel offset pattern that changes at each shutter frame, under the scene of an
// image (3000 + i % 1000 + 3 * counter) or the shutter's flat 2500; only the shutter subtraction
// takes the pattern out. The start-up frame is a flat 6000 (every 7th pixel up to 10 more: the
// driver's threshold is then 5990) with `dead_in_startup` (active-area indices) set to 0 and 100
// alternately.

#include <algorithm>
#include <cstdint>
#include <deque>
#include <sstream>
#include <string>
#include <vector>

#include "bolo/hal/seek_source.hpp"

namespace bolo::test {

// The active area, written out here rather than taken from the model.
struct TestCrop {
  std::uint32_t x, y, width, height;
};
inline TestCrop test_crop(const hal::SeekModel& m) {
  return m.product_id == 0x0011 ? TestCrop{1, 4, 320, 240} : TestCrop{0, 1, 207, 154};
}

inline std::uint16_t seek_offset(std::size_t i, std::uint32_t epoch) {
  return static_cast<std::uint16_t>(((i * 2654435761u + epoch * 40503u) >> 7) & 0x0FFF);
}

// A raw frame's words: type and counter in their words, pixels as above.
inline std::vector<std::uint16_t> make_seek_words(const hal::SeekModel& m, std::uint16_t type, std::uint16_t counter,
                                                  std::uint32_t epoch, const std::vector<std::uint32_t>& dead = {}) {
  std::vector<std::uint16_t> w(m.pixels());
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (type == 4) w[i] = static_cast<std::uint16_t>(6000 + (i % 7 == 0 ? i % 11 : 0));
    else if (type == 3) w[i] = static_cast<std::uint16_t>(3000 + i % 1000 + 3u * counter + seek_offset(i, epoch));
    else w[i] = static_cast<std::uint16_t>(2500 + seek_offset(i, epoch));
  }
  const TestCrop c = test_crop(m);
  for (std::size_t k = 0; type == 4 && k < dead.size(); ++k) {
    const std::size_t x = c.x + dead[k] % c.width, y = c.y + dead[k] / c.width;
    w[y * m.width + x] = k % 2 ? 100 : 0;
  }
  w[m.type_word] = type;
  w[m.counter_word] = counter;
  return w;
}

inline std::vector<std::uint8_t> seek_bytes(const std::vector<std::uint16_t>& w) {
  std::vector<std::uint8_t> b(w.size() * 2);
  for (std::size_t i = 0; i < w.size(); ++i) {
    b[2 * i] = static_cast<std::uint8_t>(w[i] & 0xFF);
    b[2 * i + 1] = static_cast<std::uint8_t>(w[i] >> 8);
  }
  return b;
}

inline std::vector<std::uint8_t> make_seek_frame(const hal::SeekModel& m, std::uint16_t type, std::uint16_t counter,
                                                 std::uint32_t epoch = 0, const std::vector<std::uint32_t>& dead = {}) {
  return seek_bytes(make_seek_words(m, type, counter, epoch, dead));
}

// One expected control request: "out REQUEST BYTES..." or "in REQUEST LENGTH" (decimal request,
// hex bytes).
struct ExpectedRequest {
  bool in = false;
  std::uint8_t request = 0;
  std::vector<std::uint8_t> payload;  // out
  std::size_t length = 0;             // in
};

inline std::vector<ExpectedRequest> parse_requests(const std::vector<std::string>& lines) {
  std::vector<ExpectedRequest> out;
  for (const std::string& line : lines) {
    std::istringstream s(line);
    std::string dir;
    unsigned request = 0;
    s >> dir >> request;
    ExpectedRequest r;
    r.in = dir == "in";
    r.request = static_cast<std::uint8_t>(request);
    if (r.in) {
      s >> r.length;
    } else {
      unsigned byte = 0;
      while (s >> std::hex >> byte) r.payload.push_back(static_cast<std::uint8_t>(byte));
    }
    out.push_back(r);
  }
  return out;
}

// libseek-thermal's start-up, per model (the brief of issue 42 lists it).
inline std::vector<ExpectedRequest> expected_seek_startup(const hal::SeekModel& m) {
  if (m.product_id == 0x0010)
    return parse_requests({"out 84 01", "out 60 00 00", "in 78 4", "in 54 12",
                           "out 86 20 00 30 00 00 00", "in 88 64", "out 86 20 00 50 00 00 00", "in 88 64",
                           "out 86 0c 00 70 00 00 00", "in 88 24", "out 86 06 00 08 00 00 00", "in 88 12",
                           "out 62 08 00", "in 61 2", "out 62 08 00", "out 60 01 00", "in 61 2"});
  std::vector<std::string> pro = {"out 84 01", "out 60 00 00", "in 78 4", "in 54 12",
                                  "out 86 06 00 08 00 00 00", "in 88 12", "out 85 17 00", "in 78 64",
                                  "out 86 01 00 00 06 00 00", "in 88 2", "out 86 01 00 01 06 00 00", "in 88 2"};
  for (unsigned a = 0; a < 2560; a += 32) {
    std::ostringstream s;
    s << "out 86 20 00 " << std::hex << (a % 256) << " " << (a / 256) << " 00 00";
    pro.push_back(s.str());
    pro.push_back("in 88 64");
  }
  for (const char* l : {"out 85 15 00", "in 78 64", "out 62 08 00", "out 60 01 00"}) pro.push_back(l);
  return parse_requests(pro);
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
  struct Sent {
    std::uint16_t type;
    Fault fault;
    std::vector<std::uint16_t> words;
  };
  explicit FakeSeek(const hal::SeekModel& m) : model(m), startup(expected_seek_startup(m)) {}

  hal::Transfer control_out(std::uint8_t request, std::span<const std::uint8_t> data) override {
    log.push_back(request);
    hal::Transfer t;
    if (unplugged) {
      t.status = hal::TransferStatus::disconnected;
      return t;
    }
    const std::vector<std::uint8_t> bytes(data.begin(), data.end());
    if (fail_first_write && request == 84) {
      fail_first_write = false;
      t.status = hal::TransferStatus::error;
      return t;
    }
    if (request == 84 && bytes == std::vector<std::uint8_t>{1}) {
      position = 1;  // a (re)start
      running = false;
    } else if (expected_next(false, request) && startup[position].payload == bytes) {
      advance();
    } else if (request == 60 && bytes == std::vector<std::uint8_t>{0, 0}) {
      position = 0;  // closed: the next start must begin with TARGET_PLATFORM
      running = false;
    } else if (running && request == 83 && bytes.size() == 4) {
      requested_pixels = data[0] | data[1] << 8 | data[2] << 16 | std::uint32_t{data[3]} << 24;
      if (requested_pixels != model.pixels()) return refuse(t);
      if (unanswered_requests > 0)
        --unanswered_requests;  // not ready: the request is accepted and nothing is sent
      else
        queue_next_frame();
    } else if (running && request == 55 && bytes == std::vector<std::uint8_t>{0xFC, 0x00, 0x04, 0x00}) {
    } else {
      return refuse(t);
    }
    t.bytes = data.size();
    return t;
  }
  hal::Transfer control_in(std::uint8_t request, std::span<std::uint8_t> data) override {
    log.push_back(request);
    hal::Transfer t;
    if (unplugged) {
      t.status = hal::TransferStatus::disconnected;
      return t;
    }
    if (!expected_next(true, request) || startup[position].length != data.size()) return refuse(t);
    advance();
    for (auto& b : data) b = 0xA5;
    t.bytes = data.size();
    return t;
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
    running = false;  // a replugged camera waits for its start-up sequence again
    position = 0;
    return true;
  }

  // The image frames sent whole (a paused one too), in order, each with the latest shutter frame
  // before it.
  std::vector<std::pair<const Sent*, const Sent*>> images_with_shutter() const {
    std::vector<std::pair<const Sent*, const Sent*>> out;
    const Sent* shutter = nullptr;
    for (const Sent& s : sent) {
      if (s.type == 4) shutter = nullptr;  // a new boot
      if (s.type == 1) shutter = &s;
      if (s.type == 3 && (s.fault == Fault::none || s.fault == Fault::pause)) out.emplace_back(&s, shutter);
    }
    return out;
  }

  hal::SeekModel model;
  std::vector<ExpectedRequest> startup;
  std::size_t position = 0;  // the next start-up step expected
  bool running = false;      // the sequence went through
  std::uint32_t refused = 0;
  std::vector<std::uint16_t> boot = {4, 6, 1, 20};  // served after each completed start-up
  std::deque<Planned> booting;
  std::deque<Planned> plan;  // one entry per requested frame after the boot; type 3 when empty
  std::deque<std::pair<Fault, std::vector<std::uint8_t>>> chunks;
  std::vector<Sent> sent;
  std::vector<std::uint8_t> log;
  std::vector<std::uint32_t> dead_in_startup;
  std::uint32_t pause_timeouts = 1;  // silent reads of a pause
  std::uint32_t unanswered_requests = 0;  // the first this many frame requests get no frame
  std::uint32_t requested_pixels = 0;
  std::uint32_t epoch = 0;  // the offset pattern's; changes at each shutter frame
  std::uint16_t counter = 0;
  std::int64_t clock = 0;
  int reconnects = 0;
  bool unplugged = false, replug = true, fail_first_write = false;

 private:
  bool expected_next(bool in, std::uint8_t request) const {
    return position > 0 && position < startup.size() && startup[position].in == in &&
           startup[position].request == request;
  }
  void advance() {
    if (++position < startup.size()) return;
    running = true;
    booting.clear();
    for (std::uint16_t t : boot) booting.push_back({t});
  }
  hal::Transfer refuse(hal::Transfer t) {
    ++refused;
    t.status = hal::TransferStatus::error;
    return t;
  }
  void queue_next_frame() {
    Planned p{3};
    std::deque<Planned>& from = !booting.empty() ? booting : plan;
    if (!from.empty()) {
      p = from.front();
      from.pop_front();
    }
    counter = static_cast<std::uint16_t>(counter + p.counter_step);
    if (p.type == 1) ++epoch;
    sent.push_back({p.type, p.fault, make_seek_words(model, p.type, counter, epoch, dead_in_startup)});
    const auto frame = seek_bytes(sent.back().words);
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

// clamp(0x4000 + image - shutter) over the active area, computed here from the raw words.
inline std::vector<std::uint16_t> expected_seek_image(const hal::SeekModel& m, const std::vector<std::uint16_t>& image,
                                                      const std::vector<std::uint16_t>& shutter) {
  const TestCrop c = test_crop(m);
  std::vector<std::uint16_t> out;
  for (std::uint32_t y = c.y; y < c.y + c.height; ++y)
    for (std::uint32_t x = c.x; x < c.x + c.width; ++x) {
      const long v = 0x4000L + image[y * m.width + x] - shutter[y * m.width + x];
      out.push_back(static_cast<std::uint16_t>(std::clamp(v, 0L, 0xFFFFL)));
    }
  return out;
}

}  // namespace bolo::test
