// The command line itself: help on every command, --version, the progress bar's text.

#include <catch2/catch.hpp>

#include "bolo/progress.hpp"
#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

TEST_CASE("help on the tool and on every command", "[cli][help]") {
  const CliResult top = run_bolo({"--help"});
  CHECK(top.code == 0);
  CHECK(top.err.empty());
  for (const char* command : {"info", "correct", "render"}) CHECK(top.out.find(command) != std::string::npos);

  const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
      {"info", {"REC", "--json"}},
      {"correct", {"--tau-h", "--tau-c", "--exposure", "--readout", "--float", "--overwrite", "--bad-pixels", "--stats"}},
      {"render", {"--frame", "--contact-sheet", "--compare", "--range", "--percentile", "--agc", "--colormap",
                  "--scale", "--columns", "--count"}},
  };
  for (const auto& [command, flags] : commands) {
    const CliResult r = run_bolo({command, "--help"});
    INFO(command << ":\n" << r.out);
    CHECK(r.code == 0);
    for (const std::string& flag : flags) CHECK(r.out.find(flag) != std::string::npos);
  }
}

TEST_CASE("version flag", "[cli][help]") {
  const CliResult r = run_bolo({"--version"});
  CHECK(r.code == 0);
  CHECK(r.out.rfind("bolo 0.", 0) == 0);
}

TEST_CASE("progress bar text", "[cli][progress]") {
  CHECK(cli::Progress::format("correct", 112, 160, 54.2) == "correct  [########....]  112/160 frames  54 fps");
  CHECK(cli::Progress::format("correct", 0, 160, 0) == "correct  [............]  0/160 frames");
  CHECK(cli::Progress::format("correct", 160, 160, 900) == "correct  [############]  160/160 frames  900 fps");
}
