#pragma once
// The commands of the `bolo` tool as plain functions, so the executable and the tests run the
// same code. Each run_* function validates its options, does the work, prints a summary to `out`
// and returns 0; bad input throws (bolo::cli::Error, bolo::rec::Error, ...) and errors.hpp turns
// that into `bolo: error: <message>` and exit code 2.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "bolo/correct/correct_recording.hpp"
#include "bolo/odometry/run_odometry.hpp"

namespace bolo::cli {

// bolo info REC [--json]
struct InfoOptions {
  std::filesystem::path input;
  bool json = false;
};
int run_info(const InfoOptions& options, std::ostream& out);

// bolo correct SOURCE OUT --tau-h S --tau-c S [--exposure S] [--readout S] [--float] [--overwrite]
//              [--bad-pixels] [--stats FILE.csv] [--nominal-fps F]
struct CorrectOptions : correct::CorrectRequest {
  bool progress = true;  // progress bar (only ever when stderr is a TTY)
};
int run_correct(const CorrectOptions& options, std::ostream& out);

// bolo render REC OUT.png [--frame N | --contact-sheet] [--compare REC2]
//             [--range LO:HI | --percentile P_LO:P_HI] [--agc] [--colormap gray|iron]
//             [--scale K] [--columns C] [--count M] [--labels]
struct RenderOptions {
  std::filesystem::path input;
  std::filesystem::path output;
  std::optional<std::uint64_t> frame;  // default 0 unless contact_sheet
  bool contact_sheet = false;
  std::optional<std::filesystem::path> compare;
  std::optional<std::string> range;       // "LO:HI" in pixel units
  std::optional<std::string> percentile;  // "P_LO:P_HI", default 1:99
  bool agc = false;                       // range per shown frame instead of per recording
  bool same_range = false;                // --compare: one range for both recordings
  std::string colormap = "gray";
  std::uint32_t scale = 1;
  std::uint32_t columns = 4;
  std::uint32_t count = 16;
  bool labels = false;  // frame indices on contact-sheet tiles
};
int run_render(const RenderOptions& options, std::ostream& out);

// bolo simulate OUT [--preset NAME] [--scene NAME] [--trajectory NAME] [--frames N] [--size WxH]
//   [--fps F] [--tau S | --tau-h S --tau-c S] [--exposure S] [--readout S] [--noise C] [--noise-1f C]
//   [--bits B] [--substeps K] [--supersample N] [--distortion K1,K2,P1,P2] [--effect ID:K=V,...]...
//   [--lag exposure-readout|continuous] [--seed K] [--overwrite]
struct SimulateOptions {
  std::filesystem::path output;
  std::string preset = "generic";
  std::string scene = "demo";
  std::string trajectory;              // default: the scene's own (demo: none; street: drive)
  std::uint64_t frames = 120;
  std::optional<std::string> size;     // default: the preset's
  std::optional<double> fps;           // default: the preset's
  std::optional<double> tau_s;         // sets both
  std::optional<double> tau_h_s, tau_c_s;
  std::optional<double> exposure_s;    // default: half the frame period
  std::optional<double> readout_s;     // default: the rest of the frame period
  std::optional<double> alternate_exposure_s;  // with alternate_every: the exposure switches to it
  std::uint32_t alternate_every = 0;   // frames between exposure switches (0: none)
  double timing_jitter = 0.0;          // relative spread of each frame's exposure and readout
  std::optional<double> noise;         // counts, standard deviation; default: the preset's
  double noise_1f = 0.0;
  std::optional<std::uint32_t> bits;   // default: the preset's
  std::string lag = "exposure-readout";  // how a pixel forms its reading (sim::PixelLag)
  std::uint32_t substeps = 4;
  std::uint32_t supersample = 1;       // 3D scenes: N x N rays per pixel
  std::vector<double> distortion;      // 3D scenes: k1[, k2[, p1[, p2]]] of the lens (camera.json)
  std::vector<std::string> effects;
  std::uint64_t seed = 1;
  bool overwrite = false;
  bool progress = true;
};
int run_simulate(const SimulateOptions& options, std::ostream& out);

// bolo diagnose REC --out DIR [--folds K] [--min-delta-bic B] [--overwrite]
struct DiagnoseOptions {
  std::filesystem::path input;
  std::filesystem::path output;
  int folds = 4;
  double min_delta_bic = 10.0;
  bool overwrite = false;
  bool progress = true;
};
int run_diagnose(const DiagnoseOptions& options, std::ostream& out);

// bolo odometry SOURCE --out DIR [--photometric none|affine|ir|ir-loop] [--tau-init S] [--fixed-tau] [--frames N]
//               [--no-ba] [--marginalisation-prior] [--retirement spread|oldest]
//               [--keyframe-parallax rms|quantile] [--overwrite]
// The run's options as run_odometry takes them (bound by the parser), and what only the command
// line has: the source spec, the models' names, how a live source is read, the progress bar.
struct OdometryOptions : odo::OdometryOptions {
  std::filesystem::path input;  // a recording folder, file:REC or a source spec
  std::string photometric_name = "none";
  std::string retirement_name = vo::to_string(vo::VoConfig{}.retirement);
  std::string keyframe_parallax_name = vo::to_string(vo::VoConfig{}.keyframe_parallax);
  std::uint64_t max_faults = 50;
  bool progress_bar = true;
};
int run_odometry(const OdometryOptions& options, std::ostream& out);

// bolo evaluate RUN [--truth FILE] [--json FILE] [--rpe-delta S]
struct EvaluateOptions {
  std::filesystem::path run;
  std::optional<std::filesystem::path> truth;
  std::optional<std::filesystem::path> json;
  double rpe_delta_s = 1.0;
  bool refined = false;
};
int run_evaluate(const EvaluateOptions& options, std::ostream& out);

// The whole command line: parses argv (CLI11), runs the chosen command, and reports errors.
// Help and --version go to `out`; errors go to `err` as one `bolo: error: ...` line. Returns the
// process exit code: 0 on success, 2 on bad input or a usage error.
int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace bolo::cli
