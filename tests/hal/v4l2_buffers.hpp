#pragma once
// Test buffers as the V4L2 driver hands them over: the bytes, its frame number, a monotonic time
// stamp (9 frames/s, as a Lepton streams).

#include <cstdint>
#include <vector>

#include "bolo/hal/v4l2_source.hpp"

namespace bolo::test {

inline hal::V4l2BufferStream::Buffer filled(const std::vector<std::uint8_t>& bytes, std::uint32_t sequence) {
  hal::V4l2BufferStream::Buffer b;
  b.bytes = bytes;
  b.sequence = sequence;
  b.timestamp_monotonic = true;
  b.timestamp_ns = std::int64_t{sequence} * 111'000'000;
  return b;
}

}  // namespace bolo::test
