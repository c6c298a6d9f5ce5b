#pragma once
// Helpers for the diagnosis tests: small simulated recordings made with `bolo simulate` in-process
// and `bolo diagnose` run on them, the result read back through read_diagnosis_json.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../cli/cli_test_support.hpp"
#include "../test_skip.hpp"
#include "bolo/diagnose/diagnose.hpp"
#include "bolo/recording/recording.hpp"

namespace bolo::test {

// 80x60, 120 frames at 30 fps, white noise 2 counts, input constant within each exposure (the
// baseline two-frame model is then exact) - small enough for the sanitizer builds.
inline fs::path simulate(const TempDir& tmp, const std::string& name, const std::vector<std::string>& effects,
                         int seed, const std::vector<std::string>& extra = {}) {
  const fs::path rec = tmp / name;
  std::vector<std::string> args = {"simulate", rec.string(), "--noise", "2", "--seed", std::to_string(seed)};
  // Defaults the case may override (an option given twice is refused).
  for (const auto& [option, value] : {std::pair<std::string, std::string>{"--size", "80x60"}, {"--substeps", "1"}})
    if (std::find(extra.begin(), extra.end(), option) == extra.end()) {
      args.push_back(option);
      args.push_back(value);
    }
  if (std::find(extra.begin(), extra.end(), "--frames") == extra.end()) {
    args.push_back("--frames");
    args.push_back("120");
  }
  for (const auto& e : effects) { args.push_back("--effect"); args.push_back(e); }
  args.insert(args.end(), extra.begin(), extra.end());
  const CliResult r = run_bolo(args);
  INFO(r.err);
  REQUIRE(r.code == 0);
  return rec;
}

// Adds offset(n, y, x) to every pixel of a recording's frames.npy (uint16, rounded and clamped):
// an effect made by hand, outside the simulator.
template <typename Offset>
void add_to_frames(const fs::path& rec, Offset offset) {
  const fs::path file = rec / "frames.npy";
  const rec::NpyHeader h = rec::read_npy_header(file);
  const std::uint64_t N = h.shape[0], H = h.shape[1], W = h.shape[2];
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  std::vector<unsigned char> row(W * 2);
  for (std::uint64_t n = 0; n < N; ++n)
    for (std::uint64_t y = 0; y < H; ++y) {
      const auto at = static_cast<std::streamoff>(h.data_offset + ((n * H + y) * W) * 2);
      f.seekg(at);
      f.read(reinterpret_cast<char*>(row.data()), static_cast<std::streamsize>(row.size()));
      for (std::uint64_t x = 0; x < W; ++x) {
        const double v = double(row[2 * x] | (row[2 * x + 1] << 8)) + offset(n, y, x);
        const auto u = static_cast<unsigned>(std::lround(std::clamp(v, 0.0, 65535.0)));
        row[2 * x] = static_cast<unsigned char>(u & 0xFF);
        row[2 * x + 1] = static_cast<unsigned char>(u >> 8);
      }
      f.seekp(at);
      f.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size()));
    }
  REQUIRE(f.good());
}

inline nlohmann::json diagnose(const fs::path& rec, const fs::path& out) {
  const CliResult r = run_bolo({"diagnose", rec.string(), "--out", out.string(), "--no-progress"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string text = read_text(out / "diagnosis.json");
  diag::read_diagnosis_json(text);  // the contract's shape, or it throws naming the field
  return nlohmann::json::parse(text);
}

// How many unexplained entries have `text` in their summary.
inline int unexplained_with(const nlohmann::json& d, const std::string& text) {
  int n = 0;
  for (const auto& u : d["unexplained"]) n += u["where"]["summary"].get<std::string>().find(text) != std::string::npos;
  return n;
}

inline std::vector<std::string> found(const nlohmann::json& d) {
  std::vector<std::string> ids;
  for (const auto& f : d["findings"]) ids.push_back(f["effect"].get<std::string>());
  return ids;
}

inline const nlohmann::json* finding(const nlohmann::json& d, const std::string& id) {
  for (const auto& f : d["findings"])
    if (f["effect"] == id) return &f;
  return nullptr;
}

// $BOLO_NUMPY_PYTHON, python3 or /usr/bin/python3: the first that imports numpy ("" if none).
inline std::string numpy_python() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("BOLO_NUMPY_PYTHON")) candidates.push_back(env);
  candidates.push_back("python3");
  candidates.push_back("/usr/bin/python3");
  for (const auto& py : candidates)
    if (std::system(("\"" + py + "\" -c 'import numpy' > /dev/null 2>&1").c_str()) == 0) return py;
  return "";
}

// Writes tmp / name with the study's second, independent generator (scripts/study/
// independent_generator.py) for `case_and_options` ("effect:shading --seed 1 ..."); the empty path
// when no Python imports NumPy, after marking the test skipped (the caller returns).
inline fs::path second_generator(const TempDir& tmp, const std::string& name, const std::string& case_and_options) {
  const std::string python = numpy_python();
  if (python.empty()) {
    skip("no Python with NumPy for scripts/study/independent_generator.py (set BOLO_NUMPY_PYTHON)");
    return {};
  }
  const fs::path rec = tmp / name;
  const std::string generator = std::string(BOLO_TESTS_DIR) + "/../scripts/study/independent_generator.py";
  const std::string command =
      "\"" + python + "\" \"" + generator + "\" \"" + rec.string() + "\" --case " + case_and_options + " > /dev/null";
  REQUIRE(std::system(command.c_str()) == 0);
  return rec;
}

// A second-generator recording's diagnosis `d` names exactly `effect`, with `param` within
// `epsilon` (relative) of the generator's truth for it.
inline void check_one_finding(const nlohmann::json& d, const fs::path& rec, const std::string& effect,
                              const std::string& param, double epsilon) {
  INFO(d["findings"].dump(1));
  REQUIRE(d["findings"].size() == 1);
  CHECK(d["findings"][0]["effect"] == effect);
  const nlohmann::json truth = nlohmann::json::parse(read_text(rec / "truth" / "effects.json"));
  const double expected = truth["effects"][effect][param].get<double>();
  CHECK(d["findings"][0]["params"][param].get<double>() == Approx(expected).epsilon(epsilon));
}

// Rewrites `from`'s frames.csv into `to`: each data row's cells (padded to the 7 columns of the
// shared format) pass through `edit` with the row's number; the header is kept.
template <typename Edit>
void edit_frames_csv(const fs::path& from, const fs::path& to, Edit&& edit) {
  std::istringstream in(read_text(from));
  std::string line, text;
  std::getline(in, line);
  text = line + "\n";
  for (int row = 0; std::getline(in, line); ++row) {
    std::vector<std::string> cells;
    std::stringstream cell_stream(line);
    for (std::string cell; std::getline(cell_stream, cell, ',');) cells.push_back(cell);
    while (cells.size() < 7) cells.emplace_back();
    edit(row, cells);
    for (std::size_t c = 0; c < cells.size(); ++c) text += (c ? "," : "") + cells[c];
    text += "\n";
  }
  std::ofstream(to, std::ios::binary) << text;
}

}  // namespace bolo::test
