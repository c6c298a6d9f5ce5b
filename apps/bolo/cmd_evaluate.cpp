// bolo evaluate RUN [--truth poses.tum] [--json FILE] [--refined]: a VO run against ground truth.

#include <memory>

#include "bolo/commands.hpp"
#include "bolo/errors.hpp"
#include "bolo/odometry/evaluate.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {

int run_evaluate(const EvaluateOptions& o, std::ostream& out) {
  if (!std::filesystem::is_directory(o.run)) fail(o.run.string(), ": not a folder (expected a `bolo odometry` output)");
  if (!(o.rpe_delta_s > 0)) fail("--rpe-delta: must be positive, got ", o.rpe_delta_s);
  odo::EvaluateOptions options;
  options.run = o.run;
  options.truth = o.truth;
  options.rpe_delta_s = o.rpe_delta_s;
  if (o.refined) options.trajectory = "trajectory-refined.tum";
  const odo::Evaluation e = odo::evaluate_run(options);
  out << "evaluate: " << o.run.string() << '\n' << odo::to_table(e);
  if (o.json) rec::write_file_atomically(*o.json, odo::to_json(e).dump(2) + "\n");
  return kExitOk;
}

Command add_evaluate_command(CLI::App& parent) {
  auto o = std::make_shared<EvaluateOptions>();
  CLI::App* app = add_command(
      parent, "evaluate", "Evaluate a VO run against ground truth: ATE, RPE, map and line fits",
      "Reads a `bolo odometry` output folder and the ground truth (poses.tum of the recording\n"
      "named in its summary.json, or --truth) and prints: ATE (RMSE after Sim(3) Umeyama\n"
      "alignment), RPE over --rpe-delta seconds (translation after scaling, rotation), keyframes,\n"
      "total tracked points, map points on the road plane (|z| < 0.3 m after alignment) with the\n"
      "plane fit's RMSE/std, line fits of the camera positions on straight segments of the true\n"
      "path (heading within 2 degrees for >= 1 s), and the tau estimate against the simulation's\n"
      "truth/effects.json when present. A run that restarted after losing the track is a chain of\n"
      "maps, each with its own scale and origin: each tracking segment is also aligned on its own\n"
      "(its ATE and scale; the ATE over the segments). --json writes the same as one JSON object.");
  app->add_option("RUN", o->run, "Output folder of `bolo odometry`")->required();
  app->add_option("--truth", o->truth, "Ground-truth TUM file (default: <recording>/poses.tum)");
  app->add_option("--json", o->json, "Write the metrics as JSON to this file");
  app->add_option("--rpe-delta", o->rpe_delta_s, "RPE interval, seconds (default 1)");
  app->add_flag("--refined", o->refined,
                "Score trajectory-refined.tum (every pose carried on its keyframe's last pose, as DSO's and "
                "ORB-SLAM's end-of-run trajectories) instead of trajectory.tum (the poses as tracked)");
  return {app, [o](std::ostream& out) { return run_evaluate(*o, out); }};
}

}  // namespace bolo::cli
