#pragma once
// Test buffers as the V4L2 driver hands them over: the bytes, its frame number, a monotonic time
// stamp (9 frames/s, as a Lepton streams).

#include <cstdint>
#include <vector>

#include "bolo/firmware/two_frame_corrector.hpp"
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

// The corrector the V4L2 stream tests feed: tau 12 ms, a Lepton's 10 ms exposure / 6 ms readout.
inline fw::CorrectorConfig lepton_corrector_config(std::uint32_t width, std::uint32_t height) {
  fw::CorrectorConfig config;
  config.width = width;
  config.height = height;
  config.tau = {12'000'000, 12'000'000};
  config.default_exposure_ns = 10'000'000;
  config.default_readout_ns = 6'000'000;
  return config;
}

}  // namespace bolo::test
