// Writes what the diagnosis baseline makes of a recording's motion within the exposure, for
// scripts/study/motion_term_oracle.py to compare with the generator's truth:
//   baseline.npy         the baseline's prediction (N, H, W)
//   within_exposure.npy  its term for motion within the exposure (timing shift and flow term)
//   flow_dy.npy, flow_dx.npy  the sub-pixel flow out of each frame (to frame n + 1; the last 0),
//                        on frame n + 1's pixels, pixels per frame
// usage: diagnose_motion_term_experiment RECORDING OUT_DIR

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <vector>

#include "bolo/diagnose/baseline.hpp"
#include "bolo/effects/scene_flow.hpp"
#include "bolo/recording/recording.hpp"

namespace {

void write(const std::filesystem::path& file, const bolo::diag::Frames& shape, std::span<const float> values) {
  std::ofstream out(file, std::ios::binary);
  out << bolo::rec::encode_npy_f4({std::uint64_t(shape.n), std::uint64_t(shape.height), std::uint64_t(shape.width)}, values);
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s RECORDING OUT_DIR\n", argv[0]);
    return 2;
  }
  try {
    bolo::diag::DiagnoseData d = bolo::diag::load_for_diagnosis(argv[1]);
    const bolo::diag::BaselineFit fit = bolo::diag::fit_baseline(d);
    const std::filesystem::path out = argv[2];
    std::filesystem::create_directories(out);
    write(out / "baseline.npy", d.shape, d.baseline);
    std::vector<float> within = d.within_exposure;
    within.resize(d.shape.size(), 0.0f);
    write(out / "within_exposure.npy", d.shape, within);
    if (d.input_flow_dy.empty() && d.has_scene) bolo::diag::fill_input_flow(d);
    std::vector<float> all_dy, all_dx, dy, dx;
    for (int n = 0; n < d.shape.n; ++n) {
      bolo::diag::subpixel_input_flow(d, n + 1 < d.shape.n ? n : -1, dy, dx);
      dy.resize(d.shape.pixels(), 0.0f);
      dx.resize(d.shape.pixels(), 0.0f);
      all_dy.insert(all_dy.end(), dy.begin(), dy.end());
      all_dx.insert(all_dx.end(), dx.begin(), dx.end());
    }
    write(out / "flow_dy.npy", d.shape, all_dy);
    write(out / "flow_dx.npy", d.shape, all_dx);
    std::printf("%s\n", fit.to_json().dump().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
