#pragma once
// stats.csv, the VO's log of every frame: `bolo odometry` writes it, `bolo evaluate` and the tests
// read it. One row per recording frame fed to the VO.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bolo::odo {

struct StatsRow {
  std::uint64_t index = 0;  // the recording's frame index
  double t_s = 0;
  std::string state;        // vo::to_string(TrackingState)
  std::uint32_t tracked_points = 0;
  bool keyframe = false;
  double residual_rms = 0;
  double tau_h_s = 0, tau_c_s = 0;
  double time_ms = 0;  // the VO's processing time for the frame
};

// The header line, with its newline.
const char* stats_csv_header();
// One row as a line, with its newline.
std::string stats_csv_line(const StatsRow& row);
// Throws Error naming the file and line for a missing file, another header, a row without 9
// columns or a cell that is not a number where one is expected.
std::vector<StatsRow> read_stats_csv(const std::filesystem::path& file);

}  // namespace bolo::odo
