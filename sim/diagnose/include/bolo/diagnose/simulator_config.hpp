#pragma once
// The simulator configuration `bolo diagnose` writes (simulate.cfg) and `bolo simulate --config`
// reads: one `option = value` per line (option = a long flag of `bolo simulate` without the
// dashes), strings in double quotes, a repeatable option as ["a", "b"], `#` starts a comment.
//   size = "160x120"
//   tau-c = 0.012
//   effect = ["column_fpn:sigma=3", "ffc_step:frames=40/90,step=1,flagged=0"]

#include <string>
#include <utility>
#include <vector>

namespace bolo::diag {

struct ConfigEntry {
  std::string option;
  std::vector<std::string> values;
  int line = 0;
};

// Throws std::runtime_error "<source>: line N: <what>" on a malformed line.
std::vector<ConfigEntry> parse_simulator_config(const std::string& text, const std::string& source);

}  // namespace bolo::diag
