#pragma once
// The UVC side of the emulated PureThermal (FLIR Lepton on a PureThermal board): its Y16 format
// with the 160x120 and 160x122 (two telemetry rows) frames, and the video probe/commit control
// (UVC 1.1, 4.3.1.1) the host negotiates before it streams. Pure: no I/O.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace bolo::hil::uvc {

struct FrameSize {
  std::uint16_t width = 0, height = 0;
  std::uint32_t bytes() const { return std::uint32_t{width} * height * 2; }
};

// Format 1 (Y16); frame index i + 1 is kFrames[i].
inline constexpr std::array<FrameSize, 2> kFrames{{{160, 120}, {160, 122}}};
inline constexpr std::uint32_t kFrameInterval = 1111111;  // 100 ns units: 9 frames/s
inline constexpr std::uint32_t kClockFrequency = 48'000'000;
// GUID of the uncompressed Y16 format (16-bit greyscale): 'Y' '1' '6' ' ' + the UVC base GUID.
inline constexpr std::array<std::uint8_t, 16> kGuidY16{'Y', '1', '6', ' ', 0x00, 0x00, 0x10, 0x00,
                                                       0x80, 0x00, 0x00, 0xaa, 0x00, 0x38, 0x9b, 0x71};

// Requests (UVC 1.1, A.8) and the streaming interface's control selectors (A.9.7).
enum Request : std::uint8_t {
  kSetCur = 0x01, kGetCur = 0x81, kGetMin = 0x82, kGetMax = 0x83, kGetRes = 0x84, kGetLen = 0x85,
  kGetInfo = 0x86, kGetDef = 0x87,
};
enum Selector : std::uint8_t { kProbe = 0x01, kCommit = 0x02 };

// The 34-byte video probe and commit control (26 bytes up to dwMaxPayloadTransferSize for
// UVC 1.0 hosts), little endian on the wire.
struct StreamingControl {
  std::uint16_t hint = 0;
  std::uint8_t format_index = 0;
  std::uint8_t frame_index = 0;
  std::uint32_t frame_interval = 0;
  std::uint16_t key_frame_rate = 0, p_frame_rate = 0, comp_quality = 0, comp_window_size = 0, delay = 0;
  std::uint32_t max_video_frame_size = 0;
  std::uint32_t max_payload_transfer_size = 0;
  std::uint32_t clock_frequency = 0;
  std::uint8_t framing_info = 0, preferred_version = 0, min_version = 0, max_version = 0;

  static constexpr std::size_t kBytes = 34;
  std::vector<std::uint8_t> encode(std::size_t length) const;  // the first `length` bytes
  // Fields the bytes do not reach keep their value from `base`.
  static StreamingControl decode(std::span<const std::uint8_t> bytes, const StreamingControl& base);
  bool operator==(const StreamingControl&) const = default;
};

// What the device offers for format/frame indices (1-based), completed with the sizes, interval
// and payload the device streams with: out-of-range indices become the first format/frame, as a
// device settles a probe on values it supports.
StreamingControl settle(const StreamingControl& requested, std::uint32_t max_payload);
// The default (GET_DEF, GET_MIN), and the maximum (GET_MAX: the last frame).
StreamingControl default_control(std::uint32_t max_payload);
StreamingControl maximum_control(std::uint32_t max_payload);

// The frame a settled control selects.
FrameSize frame_of(const StreamingControl& settled);

// The answer to a class request on the streaming interface's probe/commit control: data for IN
// requests, nothing to stall. `current` is the probe's (or commit's) current value.
std::optional<std::vector<std::uint8_t>> answer(std::uint8_t request, std::uint8_t selector, std::uint16_t length,
                                                const StreamingControl& current, std::uint32_t max_payload);

}  // namespace bolo::hil::uvc
