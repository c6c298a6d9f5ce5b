#pragma once
// FNV-1a, 64 bit: what an emulator logs for a frame it sends and what a host-side HIL program
// computes over what it received, so the two can be compared frame by frame.

#include <cstddef>
#include <cstdint>

namespace bolo::hil {

inline constexpr std::uint64_t kFnvOffset = 0xcbf29ce484222325ULL;

inline std::uint64_t fnv1a_add(std::uint64_t h, std::uint8_t byte) { return (h ^ byte) * 0x100000001b3ULL; }

inline std::uint64_t fnv1a_add(std::uint64_t h, const std::uint8_t* data, std::size_t size) {
  for (std::size_t i = 0; i < size; ++i) h = fnv1a_add(h, data[i]);
  return h;
}

// 16-bit pixels as the little-endian bytes the cameras send them as.
template <class Pixels>
std::uint64_t fnv1a_add_pixels_le(std::uint64_t h, const Pixels& pixels) {
  for (std::uint16_t p : pixels) h = fnv1a_add(fnv1a_add(h, static_cast<std::uint8_t>(p & 0xFF)), static_cast<std::uint8_t>(p >> 8));
  return h;
}

}  // namespace bolo::hil
