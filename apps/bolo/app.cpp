// The command line: builds the CLI11 application, registers the commands, parses, dispatches.

#include <string>
#include <vector>

#include "bolo/commands.hpp"
#include "bolo/errors.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  return guarded(err, [&]() -> int {
    CLI::App app{
        "bolo " BOLO_VERSION ": photometric (ghosting) correction and tools for uncooled\n"
        "microbolometer cameras. Recordings are folders in the shared format (recording.json,\n"
        "frames.npy, frames.csv); see `bolo COMMAND --help`.",
        "bolo"};
    app.set_version_flag("--version", "bolo " BOLO_VERSION);
    app.require_subcommand(1);
    const std::vector<Command> commands = {add_info_command(app), add_correct_command(app),
                                           add_render_command(app), add_simulate_command(app),
                                           add_capture_command(app), add_devices_command(app),
                                           add_diagnose_command(app), add_odometry_command(app),
                                           add_evaluate_command(app), add_run_command(app, err)};
    app.footer(kExitCodesHelp);  // after the commands: each has its own footer
    // CLI11 would only say "A subcommand is required" for a mistyped command: name it.
    if (argc > 1 && argv[1][0] != '-') {
      const std::string word = argv[1];
      bool known = false;
      std::string names;
      for (const Command& command : commands) {
        known = known || command.app->get_name() == word;
        names += (names.empty() ? "" : ", ") + command.app->get_name();
      }
      if (!known) {
        print_error(err, word + ": unknown command (commands: " + names + "; see `bolo --help`)");
        return kExitError;
      }
    }
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      if (e.get_exit_code() == 0) return app.exit(e, out, err);  // --help, --version
      std::string message = e.what();
      const std::vector<CLI::App*> chosen = app.get_subcommands();
      message += chosen.empty() ? " (see `bolo --help`)"
                                : " (see `bolo " + chosen.front()->get_name() + " --help`)";
      print_error(err, message);
      return kExitError;
    }
    for (const Command& command : commands)
      if (command.app->parsed()) return command.action(out);
    print_error(err, "no command given (see `bolo --help`)");
    return kExitError;
  });
}

}  // namespace bolo::cli
