// bolo evaluate's tracking segments: a run that restarted is a chain of maps, each with its own
// scale and origin. Built by hand here (no VO run): every segment is an exact similarity of the
// ground truth, so each aligned on its own fits to rounding, while one alignment of the whole
// trajectory cannot.

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "bolo/odometry/evaluate.hpp"
#include "bolo/odometry/stats_csv.hpp"
#include "bolo/odometry/trajectory_plot.hpp"
#include "bolo/odometry/tum.hpp"
#include "../test_support.hpp"

using namespace bolo;

namespace {

constexpr double kFps = 60;

// A walk along a curve with a slow turn of the camera.
vo::Se3 truth_pose(int frame) {
  const double t = frame / kFps;
  vo::Se3 T;
  T.t = vo::Vec3(1.2 * t, 0.8 * std::sin(0.9 * t), 1.5 + 0.1 * std::cos(2.0 * t));
  T.R = Eigen::AngleAxisd(0.3 * t, vo::Vec3::UnitZ()).toRotationMatrix();
  return T;
}

// The estimate of one segment: the truth seen through a similarity (the map's own frame).
vo::Se3 in_map(const vo::Se3& truth, double scale, const vo::Mat3& R, const vo::Vec3& t) {
  vo::Se3 T;
  T.R = R * truth.R;
  T.t = scale * (R * truth.t) + t;
  return T;
}

struct Row {
  int first, last;  // frames, inclusive
  const char* state;
};

// A `bolo odometry` output folder: frames in `rows`, those tracking posed in map `map_of(frame)`.
template <typename MapOf>
void write_run(const std::filesystem::path& run, const std::filesystem::path& truth_file, int frames,
               std::initializer_list<Row> rows, MapOf map_of) {
  std::filesystem::create_directories(run);
  std::ofstream truth(truth_file), est(run / "trajectory.tum"), stats(run / "stats.csv");
  stats << odo::stats_csv_header();
  for (int i = 0; i < frames; ++i) truth << odo::tum_line({i / kFps, truth_pose(i)}) << '\n';
  for (const Row& r : rows)
    for (int i = r.first; i <= r.last; ++i) {
      const bool posed = std::string(r.state) == "tracking";
      stats << odo::stats_csv_line({static_cast<std::uint64_t>(i), i / kFps, r.state, posed ? 200u : 0u, false, 1.0, 0.01,
                                    0.01, 1.0});
      if (posed) est << odo::tum_line({i / kFps, map_of(i)}) << '\n';
    }
  std::ofstream(run / "points.ply") << "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                                       "property float z\nend_header\n";
  std::ofstream(run / "summary.json") << nlohmann::json{{"photometric", "none"}, {"recording", run.string()},
                                                        {"reinitialisations", 2}}.dump();
}

}  // namespace

TEST_CASE("evaluate aligns each tracking segment between restarts on its own", "[vo][evaluate]") {
  test::TempDir tmp;
  const vo::Mat3 turn = Eigen::AngleAxisd(0.7, vo::Vec3(0.2, 0.3, 1.0).normalized()).toRotationMatrix();
  // Three maps: the first at half the scale, the second at twice it, turned and moved; the third
  // is two poses long (a restart just before the recording ends).
  const auto map_of = [&](int frame) {
    if (frame < 100) return in_map(truth_pose(frame), 0.5, vo::Mat3::Identity(), vo::Vec3(0.1, 0, 0));
    if (frame < 200) return in_map(truth_pose(frame), 2.0, turn, vo::Vec3(-3, 1, 2));
    return in_map(truth_pose(frame), 0.3, turn.transpose(), vo::Vec3::Zero());
  };
  write_run(tmp / "run", tmp / "run" / "poses.tum", 215,
            {{0, 9, "initialising"}, {10, 89, "tracking"}, {90, 97, "lost"}, {98, 109, "initialising"},
             {110, 189, "tracking"}, {190, 197, "lost"}, {198, 211, "initialising"}, {212, 213, "tracking"},
             {214, 214, "lost"}},
            map_of);

  odo::EvaluateOptions options;
  options.run = tmp / "run";
  const odo::Evaluation e = odo::evaluate_run(options);
  CHECK(e.posed == 80 + 80 + 2);
  REQUIRE(e.segments.size() == 3);
  // One alignment of the whole trajectory cannot fit maps of different scales.
  CHECK(e.ate_rmse_relative > 0.05);
  const odo::TrackedSegment& first = e.segments[0];
  const odo::TrackedSegment& second = e.segments[1];
  CHECK(first.poses == 80);
  CHECK(first.first_t == Approx(10 / kFps).margin(1e-6));
  CHECK(first.last_t == Approx(89 / kFps).margin(1e-6));
  REQUIRE(first.ate_rmse);
  CHECK(*first.ate_rmse < 1e-4);  // TUM lines keep 6 decimals
  CHECK(first.scale == Approx(2.0).epsilon(1e-4));
  CHECK(second.poses == 80);
  REQUIRE(second.ate_rmse);
  CHECK(*second.ate_rmse < 1e-4);
  CHECK(second.scale == Approx(0.5).epsilon(1e-4));
  CHECK(e.segments[2].poses == 2);
  CHECK(e.segments[2].number == 3);
  CHECK_FALSE(e.segments[2].ate_rmse);
  CHECK(e.segments_ate_rmse < 1e-4);
  CHECK(first.path_length_m + second.path_length_m > 2.0);

  const nlohmann::json j = odo::to_json(e);
  REQUIRE(j["segments"].size() == 3);
  CHECK(j["segments"][2]["ate_rmse_m"].is_null());
  CHECK(j["segments"][1]["poses"] == 80);
  const std::string table = odo::to_table(e);
  CHECK(table.find("tracking segments            3") != std::string::npos);
  CHECK(table.find("too short to align") != std::string::npos);
  CHECK(table.find("segment 3 ") != std::string::npos);
}

TEST_CASE("evaluate: a run without a restart is one segment with the whole run's ATE", "[vo][evaluate]") {
  test::TempDir tmp;
  // A map drifting in scale (not a similarity): its one segment has the whole run's ATE.
  const auto map_of = [](int frame) { return in_map(truth_pose(frame), 1.0 + 0.004 * frame, vo::Mat3::Identity(), vo::Vec3::Zero()); };
  write_run(tmp / "run", tmp / "run" / "poses.tum", 120, {{0, 11, "initialising"}, {12, 119, "tracking"}}, map_of);
  odo::EvaluateOptions options;
  options.run = tmp / "run";
  const odo::Evaluation e = odo::evaluate_run(options);
  REQUIRE(e.segments.size() == 1);
  REQUIRE(e.segments[0].ate_rmse);
  CHECK(e.ate_rmse > 1e-3);
  CHECK(*e.segments[0].ate_rmse == Approx(e.ate_rmse).epsilon(1e-12));
  CHECK(e.segments_ate_rmse == Approx(e.ate_rmse).epsilon(1e-12));
  CHECK(e.segments_ate_relative == Approx(e.ate_rmse_relative).epsilon(1e-12));
  CHECK(odo::to_table(e).find("tracking segments") == std::string::npos);
}

TEST_CASE("evaluate refuses a pose without a stats row", "[vo][evaluate][refusal]") {
  test::TempDir tmp;
  const auto map_of = [](int frame) { return truth_pose(frame); };
  write_run(tmp / "run", tmp / "run" / "poses.tum", 60, {{0, 5, "initialising"}, {6, 59, "tracking"}}, map_of);
  // Rows 30.. dropped from stats.csv: the poses there name no row.
  std::ifstream in(tmp / "run" / "stats.csv");
  std::string kept, line;
  for (int n = 0; std::getline(in, line) && n <= 30; ++n) kept += line + "\n";
  in.close();
  std::ofstream(tmp / "run" / "stats.csv") << kept;
  odo::EvaluateOptions options;
  options.run = tmp / "run";
  try {
    (void)odo::evaluate_run(options);
    FAIL("expected a refusal");
  } catch (const odo::Error& error) {
    const std::string message = error.what();
    CHECK(message.find("trajectory.tum: pose at t = 0.5") != std::string::npos);
    CHECK(message.find("has no row in stats.csv") != std::string::npos);
  }
}

TEST_CASE("evaluate refuses a stats.csv that is not bolo odometry's, naming the file and line", "[vo][evaluate][refusal]") {
  test::TempDir tmp;
  const auto map_of = [](int frame) { return truth_pose(frame); };
  write_run(tmp / "run", tmp / "run" / "poses.tum", 60, {{0, 5, "initialising"}, {6, 59, "tracking"}}, map_of);
  const std::filesystem::path stats = tmp / "run" / "stats.csv";
  std::ifstream in(stats);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  in.close();
  // The file with its line `number` (from 1) replaced by `line`.
  const auto with_line = [&](int number, const std::string& line) {
    std::size_t start = 0;
    for (int n = 1; n < number; ++n) start = text.find('\n', start) + 1;
    return text.substr(0, start) + line + "\n" + text.substr(text.find('\n', start) + 1);
  };
  const auto refusal = [&](const std::string& written) {
    std::ofstream(stats) << written;
    odo::EvaluateOptions options;
    options.run = tmp / "run";
    try {
      (void)odo::evaluate_run(options);
    } catch (const odo::Error& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  CHECK(refusal(with_line(1, "frame,t")) == stats.string() + ": line 1: unexpected header (not the stats.csv of bolo odometry)");
  CHECK(refusal(with_line(4, "2,0.03,tracking,200")) == stats.string() + ": line 4: expected 9 columns");
  CHECK(refusal(with_line(4, "2,0.03,tracking,many,0,1,0.01,0.01,1")) == stats.string() + ": line 4: not a number");
  CHECK(refusal(text) == "accepted");
}

TEST_CASE("the trajectory plot draws each tracking segment aligned on its own", "[vo][evaluate][plot]") {
  std::vector<odo::StampedPose> truth, trajectory;
  std::vector<std::size_t> segment;
  for (int i = 0; i < 120; ++i) truth.push_back({i / kFps, truth_pose(i)});
  for (int i = 10; i < 50; ++i) trajectory.push_back({i / kFps, in_map(truth_pose(i), 0.5, vo::Mat3::Identity(), vo::Vec3::Zero())}), segment.push_back(0);
  for (int i = 70; i < 110; ++i) trajectory.push_back({i / kFps, in_map(truth_pose(i), 3.0, vo::Mat3::Identity(), vo::Vec3(5, 0, 0))}), segment.push_back(1);

  const auto series = odo::trajectory_series(trajectory, segment, truth, 1 / kFps, "estimate (none)");
  REQUIRE(series.size() == 3);  // the truth and two segments
  CHECK(series[0].label == "ground truth");
  CHECK(series[1].label == "estimate (none), segment 1 (aligned on its own)");
  CHECK(series[2].points.size() == 40);
  CHECK(series[1].colour != series[2].colour);
  // Each segment lands on the truth it covers.
  for (std::size_t k = 0; k < 40; ++k) {
    CHECK((series[1].points[k] - truth[10 + k].T_wc.t).norm() < 1e-9);
    CHECK((series[2].points[k] - truth[70 + k].T_wc.t).norm() < 1e-9);
  }

  // One segment: one series, aligned as a whole; without a truth, the segments still apart.
  const std::vector<odo::StampedPose> first(trajectory.begin(), trajectory.begin() + 40);
  const auto single = odo::trajectory_series(first, std::vector<std::size_t>(40, 0), truth, 1 / kFps, "estimate (ir)");
  REQUIRE(single.size() == 2);
  CHECK(single[1].label == "estimate (ir)");
  const auto untruthed = odo::trajectory_series(trajectory, segment, std::nullopt, 1 / kFps, "estimate (ir)");
  REQUIRE(untruthed.size() == 2);
  CHECK(untruthed[1].label == "estimate (ir), segment 2");
  CHECK(untruthed[1].points.front() == trajectory[40].T_wc.t);
}

TEST_CASE("the trajectory plot numbers segments as evaluate lists them", "[vo][evaluate][plot]") {
  std::vector<odo::StampedPose> truth, trajectory;
  std::vector<std::size_t> segment;
  for (int i = 0; i < 120; ++i) truth.push_back({i / kFps, truth_pose(i)});
  // Segments 0 (20 poses), 1 (2 poses: too short to align), 2 (20 poses).
  for (int i = 10; i < 30; ++i) trajectory.push_back({i / kFps, truth_pose(i)}), segment.push_back(0);
  for (int i = 50; i < 52; ++i) trajectory.push_back({i / kFps, truth_pose(i)}), segment.push_back(1);
  for (int i = 80; i < 100; ++i) trajectory.push_back({i / kFps, truth_pose(i)}), segment.push_back(2);
  const auto series = odo::trajectory_series(trajectory, segment, truth, 1 / kFps, "estimate (ir)");
  REQUIRE(series.size() == 3);
  CHECK(series[1].label == "estimate (ir), segment 1 (aligned on its own)");
  CHECK(series[2].label == "estimate (ir), segment 3 (aligned on its own)");
}
