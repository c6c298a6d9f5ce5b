// Main of test_diagnose_shared: Catch2's, with the skip of shared_data.hpp turned into the exit
// code ctest reads as skipped.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "shared_data.hpp"

namespace bolo::test {
bool& shared_data_missing() {
  static bool missing = false;
  return missing;
}
}  // namespace bolo::test

int main(int argc, char** argv) {
  const int failed = Catch::Session().run(argc, argv);
  return failed == 0 && bolo::test::shared_data_missing() ? bolo::test::kSkipExitCode : failed;
}
