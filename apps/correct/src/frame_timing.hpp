#pragma once
// The exposure and readout each frame is corrected with, resolved (and every frame's coefficients
// checked) before anything runs: the corrector would otherwise pass a frame through uncorrected.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bolo/core/frame_header.hpp"
#include "bolo/correct/correct_recording.hpp"
#include "bolo/firmware/corrector_coefficients.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::correct {

struct FrameTiming {
  std::uint32_t exposure_ns = 0, readout_ns = 0;
  double exposure_s = 0, readout_s = 0;
  bool exposure_from_flag = false, readout_from_flag = false;
};

// A flag's time (seconds) when given, and as firmware nanoseconds.
struct Defaults {
  std::optional<double> seconds;
  std::uint32_t ns = 0;
};

// A time given on the command line, as firmware nanoseconds: finite, > 0, within uint32 ns.
std::uint32_t flag_ns(const char* flag, double seconds);

// The request's flags, checked and in the firmware's units.
struct Setup {
  fw::TimeConstants tau;
  Defaults exposure, readout;
  std::uint32_t nominal_period_ns = 0;
};
// Throws Error naming the flag (--tau-h, --exposure, --nominal-fps, --frames) as typed.
Setup checked_setup(const CorrectRequest& request);

// Per frame: the frames.csv value (as the player's header has it) wins, the flag fills in.
std::vector<FrameTiming> resolve_timing(const rec::Recording& recording,
                                        std::span<const fw::FrameHeader> headers,
                                        const std::filesystem::path& csv, const Defaults& exposure,
                                        const Defaults& readout);

// A live source's frame: the header's exposure and readout (0: unknown) win, the flag fills in;
// errors name `source` and the frame.
FrameTiming timing_from_header(const fw::FrameHeader& header, const Defaults& exposure, const Defaults& readout,
                               const std::string& source, std::uint64_t frame);

void check_coefficients(const std::vector<FrameTiming>& timing, fw::TimeConstants tau,
                        const CorrectRequest& request, const std::filesystem::path& csv);
// Frame `frame`'s coefficients (with the previous frame's readout; none for the first frame);
// errors name `where` and, for a value not from a flag, `field` ("field exposure_s").
void check_coefficients_at(const FrameTiming* previous, const FrameTiming& current, std::uint64_t frame,
                           fw::TimeConstants tau, const CorrectRequest& request, const std::string& where,
                           const char* field);

}  // namespace bolo::correct
