#pragma once
// The one mapping between a frames.csv row (seconds, degrees Celsius, optional cells) and the
// FrameHeader that travels with a frame's lines (integer nanoseconds and milli-degrees).

#include <cstdint>
#include <filesystem>
#include <optional>

#include "bolo/core/frame_header.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::rec {

// Row -> header of a width x height frame. Seconds become integer nanoseconds (rounded); throws
// rec::Error naming `csv`, the frame and the field when a value does not fit (e.g. exposure over
// 4.29 s). A temperature that is not a plausible finite value becomes unknown.
fw::FrameHeader header_from_row(const FrameRow& row, std::uint32_t width, std::uint32_t height,
                                const std::filesystem::path& csv);

// Header -> row `index`. t_s is the header's time since `t0_ns`, empty when the header has no
// valid time; zero exposure or readout and unknown FFC or temperatures stay empty; temperatures
// are kept at the format's 0.01 °C.
FrameRow row_from_header(const fw::FrameHeader& header, std::uint64_t index, std::int64_t t0_ns);

// Rows of frames from a live source, in order: t_s from the first frame's time. The format needs
// increasing t_s, so a device clock that stalls or steps back leaves that frame's t_s empty
// (counted) instead of failing the recording.
class RowClock {
 public:
  FrameRow row(const fw::FrameHeader& header, std::uint64_t index);
  std::uint64_t not_increasing() const { return not_increasing_; }

 private:
  std::optional<std::int64_t> t0_, last_;
  std::uint64_t not_increasing_ = 0;
};

}  // namespace bolo::rec
