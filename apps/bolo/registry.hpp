#pragma once
// How a command file plugs into the command line: it adds its CLI11 subcommand (options bound to
// its own options struct) and returns the action that runs it once the command line is parsed.

#include <functional>
#include <string>
#include <ostream>

#include <CLI/CLI.hpp>

namespace bolo::cli {

// Footer of every help page.
inline constexpr const char* kExitCodesHelp =
    "Exit codes: 0 success, 2 bad input or usage error (one line `bolo: error: ...` on stderr\n"
    "naming the file, frame, field or flag). A failed command leaves no output behind.";

// Adds a subcommand with a one-line summary (shown in `bolo --help`) and a longer explanation
// (shown in `bolo NAME --help`, above the exit codes).
inline CLI::App* add_command(CLI::App& parent, const std::string& name, const std::string& summary,
                             const std::string& details) {
  CLI::App* app = parent.add_subcommand(name, summary);
  app->footer(details + "\n\n" + kExitCodesHelp);
  return app;
}

struct Command {
  CLI::App* app = nullptr;
  std::function<int(std::ostream& out)> action;
};

// CLI11 reads "-3" into an unsigned option as a huge number; this refuses the sign first.
inline CLI::Validator not_negative() {
  return CLI::Validator(
      [](std::string& value) {
        return !value.empty() && value[0] == '-' ? "must not be negative, got " + value : std::string();
      },
      "NON-NEGATIVE");
}

Command add_info_command(CLI::App& parent);     // cmd_info.cpp
Command add_correct_command(CLI::App& parent);  // cmd_correct.cpp
Command add_render_command(CLI::App& parent);   // cmd_render.cpp
Command add_simulate_command(CLI::App& parent);  // cmd_simulate.cpp
Command add_capture_command(CLI::App& parent);   // cmd_capture.cpp
Command add_devices_command(CLI::App& parent);   // cmd_devices.cpp
Command add_diagnose_command(CLI::App& parent);  // cmd_diagnose.cpp
Command add_odometry_command(CLI::App& parent);  // cmd_odometry.cpp
Command add_evaluate_command(CLI::App& parent);  // cmd_evaluate.cpp
// Its status lines and summary go to `err`: its stdout may carry frames (raw:-).
Command add_run_command(CLI::App& parent, std::ostream& err);  // cmd_run.cpp

}  // namespace bolo::cli
