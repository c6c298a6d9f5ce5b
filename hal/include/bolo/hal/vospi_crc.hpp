#pragma once
// The CRC of a VoSPI packet: CRC-16-CCITT (x^16 + x^12 + x^5 + 1, initial value 0, no
// reflection) over the 164-byte packet as 16-bit big-endian words, with the id's top four bits
// (the segment / T-number field) and the CRC field itself taken as zero. The FLIR ONE Pro
// delivers the words little-endian; every one of the 1260 packets of the real capture verifies
// this way (tests/hal/test_flirone_capture.cpp).

#include <cstddef>
#include <cstdint>
#include <span>

namespace bolo::hal {

constexpr std::uint16_t crc16_ccitt_step(std::uint16_t crc, std::uint8_t byte) {
  // Unsigned arithmetic throughout: integer promotion would otherwise make these shifts int.
  std::uint32_t value = crc ^ (std::uint32_t{byte} << 8u);
  for (int bit = 0; bit < 8; ++bit)
    value = (value & 0x8000u) ? (value << 1u) ^ 0x1021u : value << 1u;
  crc = static_cast<std::uint16_t>(value & 0xFFFFu);
  return crc;
}

// `packet`: id, CRC and payload as little-endian 16-bit words (an even number of bytes >= 4).
constexpr std::uint16_t vospi_crc_le_words(std::span<const std::uint8_t> packet) {
  std::uint16_t crc = 0;
  for (std::size_t i = 0; i + 1 < packet.size(); i += 2) {
    std::uint8_t hi = packet[i + 1], lo = packet[i];
    if (i == 0) hi &= 0x0Fu;
    if (i == 2) hi = lo = 0;
    crc = crc16_ccitt_step(crc, hi);
    crc = crc16_ccitt_step(crc, lo);
  }
  return crc;
}

}  // namespace bolo::hal
