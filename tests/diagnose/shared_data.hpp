#pragma once
// Tests that read ../shared/data. Catch2 2 (Debian 12's) has no SKIP(): a case that finds its
// recording absent records it here and returns; shared_data_main.cpp then exits with
// kSkipExitCode, which ctest (SKIP_RETURN_CODE) reports as skipped, not passed.

#include <cstdlib>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

namespace bolo::test {

inline constexpr int kSkipExitCode = 4;

bool& shared_data_missing();

// The folder of a shared real recording, or empty (and the run marked skipped) when absent. The
// environment variable BOLO_SHARED_DATA, when set, replaces the configured folder.
inline std::filesystem::path shared_recording_or_skip(const std::string& name) {
  const char* from_environment = std::getenv("BOLO_SHARED_DATA");
  const std::filesystem::path dir =
      std::filesystem::path(from_environment ? from_environment : BOLO_SHARED_DATA) / "real" / name;
  if (std::filesystem::exists(dir / "frames.npy")) return dir;
  WARN("SKIP: shared recording " << dir.string() << " is absent (../shared/data not beside the checkout)");
  shared_data_missing() = true;
  return {};
}

}  // namespace bolo::test
