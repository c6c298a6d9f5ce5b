#include "uvc_control.hpp"

namespace bolo::hil::uvc {

namespace {

void put(std::vector<std::uint8_t>& out, std::uint32_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

// Reads `bytes` little-endian bytes at `at` when the span reaches that far.
template <typename T>
void get(std::span<const std::uint8_t> in, std::size_t at, int bytes, T& field) {
  if (at + static_cast<std::size_t>(bytes) > in.size()) return;
  std::uint32_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= std::uint32_t{in[at + static_cast<std::size_t>(i)]} << (8 * i);
  field = static_cast<T>(v);
}

StreamingControl with_frame(std::uint8_t frame_index, std::uint32_t max_payload) {
  StreamingControl c;
  c.format_index = 1;
  c.frame_index = frame_index;
  c.frame_interval = kFrameInterval;
  c.max_video_frame_size = kFrames[frame_index - 1].bytes();
  c.max_payload_transfer_size = max_payload;
  c.clock_frequency = kClockFrequency;
  c.framing_info = 0x03;  // FID and EOF used
  c.preferred_version = c.min_version = c.max_version = 1;
  return c;
}

}  // namespace

std::vector<std::uint8_t> StreamingControl::encode(std::size_t length) const {
  std::vector<std::uint8_t> out;
  out.reserve(kBytes);
  put(out, hint, 2);
  put(out, format_index, 1);
  put(out, frame_index, 1);
  put(out, frame_interval, 4);
  put(out, key_frame_rate, 2);
  put(out, p_frame_rate, 2);
  put(out, comp_quality, 2);
  put(out, comp_window_size, 2);
  put(out, delay, 2);
  put(out, max_video_frame_size, 4);
  put(out, max_payload_transfer_size, 4);
  put(out, clock_frequency, 4);
  put(out, framing_info, 1);
  put(out, preferred_version, 1);
  put(out, min_version, 1);
  put(out, max_version, 1);
  out.resize(length < kBytes ? length : kBytes);
  return out;
}

StreamingControl StreamingControl::decode(std::span<const std::uint8_t> in, const StreamingControl& base) {
  StreamingControl c = base;
  get(in, 0, 2, c.hint);
  get(in, 2, 1, c.format_index);
  get(in, 3, 1, c.frame_index);
  get(in, 4, 4, c.frame_interval);
  get(in, 8, 2, c.key_frame_rate);
  get(in, 10, 2, c.p_frame_rate);
  get(in, 12, 2, c.comp_quality);
  get(in, 14, 2, c.comp_window_size);
  get(in, 16, 2, c.delay);
  get(in, 18, 4, c.max_video_frame_size);
  get(in, 22, 4, c.max_payload_transfer_size);
  get(in, 26, 4, c.clock_frequency);
  get(in, 30, 1, c.framing_info);
  get(in, 31, 1, c.preferred_version);
  get(in, 32, 1, c.min_version);
  get(in, 33, 1, c.max_version);
  return c;
}

StreamingControl settle(const StreamingControl& requested, std::uint32_t max_payload) {
  const bool known = requested.format_index == 1 && requested.frame_index >= 1 &&
                     requested.frame_index <= kFrames.size();
  StreamingControl c = with_frame(known ? requested.frame_index : 1, max_payload);
  c.hint = requested.hint;
  return c;
}

StreamingControl default_control(std::uint32_t max_payload) { return with_frame(1, max_payload); }

StreamingControl maximum_control(std::uint32_t max_payload) {
  return with_frame(static_cast<std::uint8_t>(kFrames.size()), max_payload);
}

FrameSize frame_of(const StreamingControl& settled) {
  if (settled.frame_index < 1 || settled.frame_index > kFrames.size()) return kFrames[0];
  return kFrames[settled.frame_index - 1];
}

std::optional<std::vector<std::uint8_t>> answer(std::uint8_t request, std::uint8_t selector, std::uint16_t length,
                                                const StreamingControl& current, std::uint32_t max_payload) {
  if (selector != kProbe && selector != kCommit) return std::nullopt;
  switch (request) {
    case kGetCur: return current.encode(length);
    case kGetMin:
    case kGetDef: return default_control(max_payload).encode(length);
    case kGetMax: return maximum_control(max_payload).encode(length);
    case kGetRes: return StreamingControl{}.encode(length);
    case kGetLen: {
      std::vector<std::uint8_t> out{static_cast<std::uint8_t>(StreamingControl::kBytes), 0};
      out.resize(length < 2 ? length : 2);
      return out;
    }
    case kGetInfo: return std::vector<std::uint8_t>{0x03};  // GET and SET supported
    default: return std::nullopt;
  }
}

}  // namespace bolo::hil::uvc
