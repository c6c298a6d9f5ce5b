#pragma once
// Skipping a test case with Catch2 2.x, which has no SKIP(): the case calls skip() and returns;
// the test main (test_main.cpp) exits with kSkipExitCode when every case it ran skipped and none
// failed, and bolo_add_test gives ctest that code as SKIP_RETURN_CODE, so ctest reports the case
// as skipped rather than passed. A run of several cases of which some skip still passes (exit 0),
// with a warning per skipped case.

#include <string>

#include <catch2/catch.hpp>

#include "support/skip_exit_code.hpp"

namespace bolo::test {

// A run that fails with kSkipExitCode failed assertions exits 1 instead (test_main.cpp), so a
// failure is never read as a skip.

struct SkipLedger {
  bool current_skipped = false;  // the running test case called skip()
  int cases_run = 0;
  int cases_skipped = 0;
};

inline SkipLedger& skip_ledger() {
  static SkipLedger ledger;
  return ledger;
}

// Marks the running test case as skipped, with the reason as a Catch2 warning. The caller returns
// right after: `if (dir.empty()) return skip("...");`.
inline void skip(const std::string& why) {
  WARN("SKIPPED: " << why);
  skip_ledger().current_skipped = true;
}

}  // namespace bolo::test
