#include "frame_timing.hpp"

#include <cmath>
#include <sstream>

#include "bolo/correct/fail.hpp"

namespace bolo::correct {
namespace fs = std::filesystem;

std::uint32_t flag_ns(const char* flag, double seconds) {
  if (!std::isfinite(seconds) || !(seconds > 0))
    fail(flag, " ", seconds_text(seconds), ": must be a finite time in seconds, > 0");
  const double ns = std::round(seconds * 1e9);
  if (ns < 1) fail(flag, " ", seconds_text(seconds), ": below the firmware's 1 ns resolution");
  if (ns > 4294967295.0)
    fail(flag, " ", seconds_text(seconds), ": too long (the firmware takes at most 4.29 s)");
  return static_cast<std::uint32_t>(ns);
}

Setup checked_setup(const CorrectRequest& o) {
  Setup setup;
  setup.tau = {flag_ns("--tau-h", o.tau_h_s), flag_ns("--tau-c", o.tau_c_s)};
  if (o.exposure_s) setup.exposure = {o.exposure_s, flag_ns("--exposure", *o.exposure_s)};
  if (o.readout_s) setup.readout = {o.readout_s, flag_ns("--readout", *o.readout_s)};
  if (o.nominal_fps) {
    if (!std::isfinite(*o.nominal_fps) || !(*o.nominal_fps > 0.25) || *o.nominal_fps > 1e6)
      fail("--nominal-fps ", seconds_text(*o.nominal_fps), ": must be a frame rate between 0.25 and 1e6");
    setup.nominal_period_ns = static_cast<std::uint32_t>(std::lround(1e9 / *o.nominal_fps));
  }
  if (o.frames && *o.frames == 0) fail("--frames 0: must be at least 1");
  return setup;
}

namespace {

// One timing field of one frame: the cell's value wins, the flag fills in where the cell is empty
// (or 0, which the firmware reads as unknown).
void resolve_field(const std::optional<double>& cell, std::uint32_t cell_ns, const Defaults& flag,
                   const fs::path& csv, std::uint64_t frame, const char* field,
                   const char* flag_name, std::uint32_t& ns, double& seconds, bool& from_flag) {
  if (cell_ns != 0) {
    ns = cell_ns;
    seconds = *cell;
    from_flag = false;
    return;
  }
  if (flag.seconds) {
    ns = flag.ns;
    seconds = *flag.seconds;
    from_flag = true;
    return;
  }
  if (!cell)
    fail(csv.string(), ": frame ", frame, ": field ", field, ": empty and no ", flag_name, " given");
  fail(csv.string(), ": frame ", frame, ": field ", field, ": ", seconds_text(*cell),
       " s is zero for the firmware (unknown) and no ", flag_name, " given");
}

}  // namespace

std::vector<FrameTiming> resolve_timing(const rec::Recording& recording,
                                        std::span<const fw::FrameHeader> headers, const fs::path& csv,
                                        const Defaults& exposure, const Defaults& readout) {
  std::vector<FrameTiming> timing(headers.size());
  for (std::size_t i = 0; i < timing.size(); ++i) {
    const rec::FrameRow& row = recording.rows()[i];
    FrameTiming& t = timing[i];
    resolve_field(row.exposure_s, headers[i].exposure_ns, exposure, csv, i, "exposure_s", "--exposure",
                  t.exposure_ns, t.exposure_s, t.exposure_from_flag);
    resolve_field(row.readout_s, headers[i].readout_ns, readout, csv, i, "readout_s", "--readout",
                  t.readout_ns, t.readout_s, t.readout_from_flag);
  }
  return timing;
}

FrameTiming timing_from_header(const fw::FrameHeader& header, const Defaults& exposure, const Defaults& readout,
                               const std::string& source, std::uint64_t frame) {
  const auto field = [&](std::uint32_t header_ns, const Defaults& flag, const char* name, const char* flag_name,
                         std::uint32_t& ns, double& seconds, bool& from_flag) {
    if (header_ns != 0) {
      ns = header_ns;
      seconds = header_ns * 1e-9;  // as frames.csv records it (rec::row_from_header)
      from_flag = false;
    } else if (flag.seconds) {
      ns = flag.ns;
      seconds = *flag.seconds;
      from_flag = true;
    } else {
      fail(source, ": frame ", frame, ": the source gives no ", name, " time and no ", flag_name, " given");
    }
  };
  FrameTiming t;
  field(header.exposure_ns, exposure, "exposure", "--exposure", t.exposure_ns, t.exposure_s, t.exposure_from_flag);
  field(header.readout_ns, readout, "readout", "--readout", t.readout_ns, t.readout_s, t.readout_from_flag);
  return t;
}

void check_coefficients_at(const FrameTiming* previous, const FrameTiming& current, std::uint64_t frame,
                           fw::TimeConstants tau, const CorrectRequest& o, const std::string& where,
                           const char* field) {
  fw::CorrectorCoefficients c;
  const fw::CoefficientStatus status =
      previous == nullptr ? fw::compute_gain_only(tau, current.exposure_ns, c)
                          : fw::compute_coefficients(tau, current.exposure_ns, previous->readout_ns, c);
  if (status == fw::CoefficientStatus::ok) return;
  std::ostringstream what;
  what << where << ": frame " << frame << ": no usable coefficients (" << fw::to_string(status) << ") for exposure "
       << seconds_text(current.exposure_s) << " s (" << (current.exposure_from_flag ? "--exposure" : field)
       << ") with --tau-h " << seconds_text(o.tau_h_s) << " --tau-c " << seconds_text(o.tau_c_s);
  if (status == fw::CoefficientStatus::gain_out_of_range)
    what << ": exposure / tau_h must be at least ~0.004 (gain 1/(1-exp(-t_e/tau_h)) below 256)";
  throw Error(what.str());
}

void check_coefficients(const std::vector<FrameTiming>& timing, fw::TimeConstants tau,
                        const CorrectRequest& o, const fs::path& csv) {
  for (std::size_t i = 0; i < timing.size(); ++i)
    check_coefficients_at(i == 0 ? nullptr : &timing[i - 1], timing[i], i, tau, o, csv.string(), "field exposure_s");
}

}  // namespace bolo::correct
