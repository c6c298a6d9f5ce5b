#pragma once
// Helpers for the diagnosis tests: small simulated recordings made with `bolo simulate` in-process
// and `bolo diagnose` run on them, the result read back through read_diagnosis_json.

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../cli/cli_test_support.hpp"
#include "bolo/diagnose/diagnose.hpp"

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

inline nlohmann::json diagnose(const fs::path& rec, const fs::path& out) {
  const CliResult r = run_bolo({"diagnose", rec.string(), "--out", out.string(), "--no-progress"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string text = read_text(out / "diagnosis.json");
  diag::read_diagnosis_json(text);  // the contract's shape, or it throws naming the field
  return nlohmann::json::parse(text);
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

}  // namespace bolo::test
