#pragma once
// Builds FLIR ONE frames byte by byte as the camera sends them (header, 63 VoSPI packets with
// valid CRCs, JPEG, JSON; or the 160x120 layout's 122 rows), for tests that need frames the
// capture does not contain.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "bolo/hal/flirone_reassembler.hpp"
#include "bolo/hal/vospi_crc.hpp"

namespace bolo::test {

struct FlirOneFrameSpec {
  std::uint16_t base = 3000;  // pixel (x, y) = base + x + 80 * y
  std::uint32_t frame_counter = 100;
  std::uint32_t last_ffc_ms = 5000;
  std::uint16_t fpa_ck = 32000, housing_ck = 32009;
  std::uint32_t status = 0x838;
  std::size_t jpeg_bytes = 300;
  std::string json = R"({"shutterState":"ON","shutterTemperature":320.5,"usbNotifiedTimestamp":100.25,"ffcState":"FFC_VALID_RAD"})";
};

inline void put_le16(std::vector<std::uint8_t>& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v & 0xFF);
  b[at + 1] = static_cast<std::uint8_t>(v >> 8);
}
inline void put_le32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  put_le16(b, at, static_cast<std::uint16_t>(v & 0xFFFF));
  put_le16(b, at + 2, static_cast<std::uint16_t>(v >> 16));
}

// Recomputes packet p's CRC (after a test changed its bytes on purpose and wants it to verify).
inline void fix_crc(std::vector<std::uint8_t>& frame, std::size_t p) {
  const std::size_t at = hal::flirone::kHeaderBytes + p * hal::flirone::kPacketBytes;
  put_le16(frame, at + 2, hal::vospi_crc_le_words({frame.data() + at, hal::flirone::kPacketBytes}));
}

// Telemetry row A's first 80 words for `s`.
inline void telemetry_row_a(const FlirOneFrameSpec& s, std::uint16_t (&words)[hal::flirone::kWidth]) {
  words[0] = 14;
  words[3] = static_cast<std::uint16_t>(s.status & 0xFFFF);
  words[4] = static_cast<std::uint16_t>(s.status >> 16);
  words[20] = static_cast<std::uint16_t>(s.frame_counter & 0xFFFF);
  words[21] = static_cast<std::uint16_t>(s.frame_counter >> 16);
  words[24] = s.fpa_ck;
  words[26] = s.housing_ck;
  words[30] = static_cast<std::uint16_t>(s.last_ffc_ms & 0xFFFF);
  words[31] = static_cast<std::uint16_t>(s.last_ffc_ms >> 16);
}

// The frame around a thermal part of `thermal_bytes`: header, JPEG, JSON; the thermal part zero.
inline std::vector<std::uint8_t> flirone_framing(const FlirOneFrameSpec& s, std::size_t thermal_bytes) {
  using namespace hal::flirone;
  const std::size_t json_bytes = s.json.size() + 1;  // the camera sends a NUL after the text
  const std::size_t total = thermal_bytes + s.jpeg_bytes + json_bytes;
  std::vector<std::uint8_t> b(kHeaderBytes + total, 0);
  put_le32(b, 0, kMagic);
  put_le32(b, 4, 1);
  put_le32(b, 8, static_cast<std::uint32_t>(total));
  put_le32(b, 12, static_cast<std::uint32_t>(thermal_bytes));
  put_le32(b, 16, static_cast<std::uint32_t>(s.jpeg_bytes));
  put_le32(b, 20, static_cast<std::uint32_t>(json_bytes));
  put_le32(b, 24, 0x12345678);
  const std::size_t jpeg_at = kHeaderBytes + thermal_bytes;
  for (std::size_t i = 0; i < s.jpeg_bytes; ++i) b[jpeg_at + i] = static_cast<std::uint8_t>(i * 7);
  for (std::size_t i = 0; i < s.json.size(); ++i)
    b[jpeg_at + s.jpeg_bytes + i] = static_cast<std::uint8_t>(s.json[i]);
  return b;
}

// The 160x120 layout as the public drivers read it: 122 rows of 328 bytes, each two halves of a
// 4-byte prefix and 80 pixels; rows 120-121 telemetry (row A's first 80 words as on the 80x60
// core). Pixel (x, y) = base + x + 160 * y.
inline std::vector<std::uint8_t> make_flirone_frame_160(const FlirOneFrameSpec& s = {}) {
  using namespace hal::flirone;
  constexpr std::size_t kRowBytes = 328, kRows = 122;
  std::vector<std::uint8_t> b = flirone_framing(s, kRows * kRowBytes);
  for (std::size_t r = 0; r < kRows; ++r)
    for (std::size_t half = 0; half < 2; ++half) {
      const std::size_t at = kHeaderBytes + r * kRowBytes + half * 164;
      put_le16(b, at, static_cast<std::uint16_t>(0xA000 | (2 * r + half)));  // prefixes: left unread
      put_le16(b, at + 2, 0xDEAD);
      std::uint16_t words[kWidth] = {};
      if (r < 120) {
        for (std::size_t x = 0; x < kWidth; ++x)
          words[x] = static_cast<std::uint16_t>(s.base + half * 80 + x + 160 * r);
      } else if (r == 120 && half == 0) {
        telemetry_row_a(s, words);
      }
      for (std::size_t x = 0; x < kWidth; ++x) put_le16(b, at + 4 + 2 * x, words[x]);
    }
  return b;
}

inline std::vector<std::uint8_t> make_flirone_frame(const FlirOneFrameSpec& s = {}) {
  using namespace hal::flirone;
  std::vector<std::uint8_t> b = flirone_framing(s, kThermalBytes);
  for (std::size_t p = 0; p < kPackets; ++p) {
    const std::size_t at = kHeaderBytes + p * kPacketBytes;
    put_le16(b, at, static_cast<std::uint16_t>(p == 0 ? 0x6000 : p));  // row 0 carries a T-number
    std::uint16_t words[kWidth] = {};
    if (p < kHeight) {
      for (std::size_t x = 0; x < kWidth; ++x) words[x] = static_cast<std::uint16_t>(s.base + x + 80 * p);
    } else if (p == kHeight) {
      telemetry_row_a(s, words);
    }
    for (std::size_t x = 0; x < kWidth; ++x) put_le16(b, at + 4 + 2 * x, words[x]);
    fix_crc(b, p);
  }
  return b;
}

// Cuts `bytes` into transfers of at most `chunk` bytes, appending them to `out`.
inline void split_into_transfers(const std::vector<std::uint8_t>& bytes, std::size_t chunk,
                                 std::vector<std::vector<std::uint8_t>>& out) {
  for (std::size_t at = 0; at < bytes.size(); at += chunk)
    out.emplace_back(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                     bytes.begin() + static_cast<std::ptrdiff_t>(std::min(bytes.size(), at + chunk)));
}

// A transfer log (flirone-log:DIR) of `frames` frames, one transfer (N.txt, hex) each, ~8.6 Hz on
// the camera's clock, the scene brightening by 40 counts a frame; the frames listed in `corrupt`
// have a pixel bit flipped (a CRC fault).
inline void write_flirone_log(const std::filesystem::path& dir, int frames, std::initializer_list<int> corrupt = {}) {
  static const char* digits = "0123456789abcdef";
  std::filesystem::create_directories(dir);
  for (int i = 0; i < frames; ++i) {
    FlirOneFrameSpec spec;
    spec.base = static_cast<std::uint16_t>(3000 + 40 * i);
    spec.frame_counter = static_cast<std::uint32_t>(3 * i);
    spec.json = R"({"shutterState":"ON","shutterTemperature":320.5,"usbNotifiedTimestamp":)" +
                std::to_string(100.0 + 0.116 * i) + R"(,"ffcState":"FFC_VALID_RAD"})";
    std::vector<std::uint8_t> f = make_flirone_frame(spec);
    for (int c : corrupt)
      if (c == i) f[1000] ^= 0x10;
    std::string text;
    for (std::uint8_t b : f) text += {digits[b >> 4], digits[b & 15]};
    std::ofstream(dir / (std::to_string(i + 1) + ".txt")) << text;
  }
}

}  // namespace bolo::test
