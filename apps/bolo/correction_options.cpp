#include "bolo/correction_options.hpp"

#include <memory>

namespace bolo::cli {

std::function<void()> add_correction_options(CLI::App& app, correct::CorrectRequest& request) {
  auto exposure = std::make_shared<double>(0.0);
  auto readout = std::make_shared<double>(0.0);
  auto nominal_fps = std::make_shared<double>(0.0);
  auto nuc = std::make_shared<std::string>();
  app.add_option("--tau-h", request.tau_h_s, "Heating time constant tau_h, seconds (e.g. 0.012)")->required();
  app.add_option("--tau-c", request.tau_c_s, "Cooling time constant tau_c, seconds (e.g. 0.012)")->required();
  CLI::Option* exposure_opt = app.add_option(
      "--exposure", *exposure, "Exposure (heating) time t_e, seconds, for frames with an empty exposure_s");
  CLI::Option* readout_opt = app.add_option(
      "--readout", *readout, "Readout (cooling) time t_r, seconds, for frames with an empty readout_s");
  CLI::Option* nuc_opt = app.add_option("--nuc", *nuc,
                 "Non-uniformity correction applied first, per pixel out = in * gain + offset: a .npy of\n"
                 "float32, shape (2, H, W), [0] the gains (0 .. 4), [1] the offsets in counts");
  app.add_flag("--bad-pixels", request.bad_pixels,
               "Replace stuck pixels (reading the 0 or 2^bits-1 rail) by the mean of their 3x3 neighbours first");
  CLI::Option* fps_opt = app.add_option(
      "--nominal-fps", *nominal_fps,
      "Frame rate for time-gap detection (default: learned from the recent t_s intervals)");
  app.add_option("--max-faults", request.max_faults,
                 "A live source's faulted frames in a row before giving up (default 50)");
  return [=, &request] {
    if (exposure_opt->count()) request.exposure_s = *exposure;
    if (readout_opt->count()) request.readout_s = *readout;
    if (fps_opt->count()) request.nominal_fps = *nominal_fps;
    if (nuc_opt->count()) request.nuc = std::filesystem::path(*nuc);
  };
}

}  // namespace bolo::cli
