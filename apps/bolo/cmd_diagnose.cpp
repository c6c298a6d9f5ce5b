// bolo diagnose REC --out DIR: where the recording departs from its baseline simulation, which
// catalogue effect explains it on held-out frames, the fitted model and what is left
// (sim/diagnose; ../shared/docs/diagnosis.md). DIR is written through a rec::AtomicFolder, so a
// failed run leaves nothing.

#include <chrono>
#include <fstream>
#include <memory>

#include "bolo/commands.hpp"
#include "bolo/diagnose/diagnose.hpp"
#include "bolo/diagnose/report.hpp"
#include "bolo/errors.hpp"
#include "bolo/progress.hpp"
#include "bolo/recording/atomic_folder.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {
namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  out.close();
  if (!out) fail(file.string(), ": cannot write");
}

}  // namespace

int run_diagnose(const DiagnoseOptions& o, std::ostream& out) {
  if (o.input.empty()) fail("no recording given: bolo diagnose REC --out DIR");
  if (o.output.empty()) fail("--out: give the folder to write diagnosis.json and report.html into");
  if (o.folds < 2 || o.folds > 20) fail("--folds: must be 2..20, got ", o.folds);
  if (!(o.min_delta_bic >= 0)) fail("--min-delta-bic: must be >= 0, got ", o.min_delta_bic);
  const fs::path dir = o.output.has_filename() ? o.output : o.output.parent_path();
  rec::AtomicFolder folder(dir, o.overwrite);  // the destination checked before the work

  diag::keep_freed_memory_for_reuse();
  const auto start = std::chrono::steady_clock::now();
  diag::DiagnoseData data = diag::load_for_diagnosis(o.input);  // throws naming the file/frame/field
  diag::Options options;
  options.folds = o.folds;
  options.min_delta_bic = o.min_delta_bic;
  diag::ResidualViews views;
  Progress progress("diagnose", 100, o.progress);
  int step = 0;
  const diag::Diagnosis result = diag::diagnose(data, options, &views, [&](const std::string&, int, int) {
    step = std::min(step + 1, 99);
    progress.update(step);
  });
  progress.finish();

  write_text(folder.path() / "diagnosis.json", diag::to_json(result).dump(2) + "\n");
  write_text(folder.path() / "report.html", diag::render_report(result, data, views, folder.path()));
  write_text(folder.path() / "simulate.cfg", diag::simulator_config(result, data));
  folder.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out << "diagnose: " << o.input.string() << ": baseline " << result.baseline.model << ", held-out RMS "
      << result.heldout_rms << " -> " << result.final_heldout_rms << " (noise floor " << result.noise_floor_rms
      << "), " << result.findings.size() << " finding(s)";
  for (const auto& f : result.findings) out << " " << f.effect;
  out << ", " << result.unexplained.size() << " unexplained; wrote " << dir.string() << " in " << seconds << " s\n";
  return kExitOk;
}

Command add_diagnose_command(CLI::App& parent) {
  auto o = std::make_shared<DiagnoseOptions>();
  CLI::App* app = add_command(
      parent, "diagnose", "Find the physics the baseline simulation left out, fit it, show the fit improve",
      "Compares REC with its baseline: the two-frame model driven by scene.npy (tau_c, gain and offset\n"
      "fitted), or, without scene.npy, a static camera (per-pixel median background, moving objects\n"
      "masked, shutter frames not taken as scene). Every effect of the catalogue\n"
      "(../shared/docs/diagnosis.md) is fitted on training blocks of frames and scored on held-out\n"
      "blocks; significant ones are kept greedily (held-out Delta BIC with a correlation-corrected\n"
      "sample size). Writes DIR/diagnosis.json, DIR/report.html (self-contained) and DIR/simulate.cfg\n"
      "(the fitted model for `bolo simulate OUT --config DIR/simulate.cfg`). Within an exposure the\n"
      "baseline moves scene.npy's frame along the measured flow; what it cannot explain is listed as\n"
      "unexplained, with where\n"
      "(limits and measured detection rates: docs/diagnosis-study.md).\n"
      "Example: bolo diagnose out/sim --out out/diag");
  app->add_option("REC", o->input, "Recording folder to diagnose");
  app->add_option("--out", o->output, "Folder to write diagnosis.json, report.html and simulate.cfg into");
  app->add_option("--folds", o->folds, "Held-out folds (blocks of frames dealt in turn)")->capture_default_str();
  app->add_option("--min-delta-bic", o->min_delta_bic, "Held-out Delta BIC a finding needs")->capture_default_str();
  app->add_flag("--overwrite", o->overwrite, "Replace DIR if it exists");
  app->add_flag("--no-progress", [o](std::int64_t) { o->progress = false; }, "Never draw the progress bar");
  return {app, [o](std::ostream& out) { return run_diagnose(*o, out); }};
}

}  // namespace bolo::cli
