// The Catch2 main of every test binary, with skipping (test_skip.hpp): exit kSkipExitCode when
// every test case run skipped and none failed.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "test_skip.hpp"

namespace {

struct SkipCounter : Catch::TestEventListenerBase {
  using TestEventListenerBase::TestEventListenerBase;
  void testCaseStarting(const Catch::TestCaseInfo& info) override {
    TestEventListenerBase::testCaseStarting(info);
    bolo::test::skip_ledger().current_skipped = false;
  }
  void testCaseEnded(const Catch::TestCaseStats& stats) override {
    auto& ledger = bolo::test::skip_ledger();
    ++ledger.cases_run;
    if (ledger.current_skipped) ++ledger.cases_skipped;
    TestEventListenerBase::testCaseEnded(stats);
  }
};

}  // namespace

CATCH_REGISTER_LISTENER(SkipCounter)

int main(int argc, char* argv[]) {
  const int rc = Catch::Session().run(argc, argv);
  const auto& ledger = bolo::test::skip_ledger();
  if (rc == 0 && ledger.cases_run > 0 && ledger.cases_skipped == ledger.cases_run) return bolo::test::kSkipExitCode;
  return rc == bolo::test::kSkipExitCode ? 1 : rc;
}
