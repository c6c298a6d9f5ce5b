#include "bolo/odometry/stats_csv.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "bolo/odometry/tum.hpp"

namespace bolo::odo {

const char* stats_csv_header() { return "index,t_s,state,tracked_points,keyframe,residual_rms,tau_h_s,tau_c_s,time_ms\n"; }

std::string stats_csv_line(const StatsRow& r) {
  char line[256];
  std::snprintf(line, sizeof line, "%llu,%.9f,%s,%u,%d,%.4f,%.6f,%.6f,%.3f\n", static_cast<unsigned long long>(r.index),
                r.t_s, r.state.c_str(), r.tracked_points, r.keyframe ? 1 : 0, r.residual_rms, r.tau_h_s, r.tau_c_s,
                r.time_ms);
  return line;
}

std::vector<StatsRow> read_stats_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot open");
  std::string line;
  std::getline(in, line);
  if (line + '\n' != stats_csv_header()) throw Error(file.string() + ": line 1: unexpected header (not the stats.csv of bolo odometry)");
  std::vector<StatsRow> rows;
  for (std::size_t n = 2; std::getline(in, line); ++n) {
    std::vector<std::string> f;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    const std::string where = file.string() + ": line " + std::to_string(n);
    if (f.size() != 9) throw Error(where + ": expected 9 columns");
    try {
      rows.push_back({std::stoull(f[0]), std::stod(f[1]), f[2], static_cast<std::uint32_t>(std::stoul(f[3])), f[4] == "1",
                      std::stod(f[5]), std::stod(f[6]), std::stod(f[7]), std::stod(f[8])});
    } catch (const std::exception&) {
      throw Error(where + ": not a number");
    }
  }
  return rows;
}

}  // namespace bolo::odo
