#pragma once
// The exit code with which a test binary says "skipped" to ctest (SKIP_RETURN_CODE 77, as the HIL
// scenarios and Automake use): the Catch2 main (test_skip.hpp) and the allocation tests' own mains.

namespace bolo::test {

inline constexpr int kSkipExitCode = 77;

}  // namespace bolo::test
