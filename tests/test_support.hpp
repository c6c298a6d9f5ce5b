#pragma once
// Helpers shared by the test binaries.

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include <catch2/catch.hpp>

#include "test_skip.hpp"

namespace bolo::test {

// Root of the shared real data: $BOLO_SHARED_DATA when set (to run the data-dependent cases
// against another copy, or to see them skip: BOLO_SHARED_DATA=/nonexistent), else the path
// configured at build time (../shared/data beside the checkout).
inline std::filesystem::path shared_data() {
  const char* env = std::getenv("BOLO_SHARED_DATA");
  return env != nullptr && *env != 0 ? std::filesystem::path(env) : std::filesystem::path(BOLO_SHARED_DATA);
}

// Folder `rel` of the shared data (it must hold `probe`). When the shared data is absent the
// running case is marked skipped (test_skip.hpp) and the path is empty, so the caller returns:
// `auto dir = shared_recording("lepton3-possum"); if (dir.empty()) return;`. When it is present
// but lacks `rel`, the case fails: the shared data is one fixed set, and a partial copy would
// otherwise leave cases passing untested.
inline std::filesystem::path shared_folder(const std::string& rel, const std::string& probe) {
  const std::filesystem::path root = shared_data();
  if (!std::filesystem::is_directory(root)) {
    skip("the shared data " + root.string() + " is absent (../shared/data beside the checkout, or $BOLO_SHARED_DATA)");
    return {};
  }
  const std::filesystem::path dir = root / rel;
  INFO("the shared data " << root.string() << " is present but lacks " << (dir / probe).string());
  REQUIRE(std::filesystem::exists(dir / probe));
  return dir;
}

// A shared real recording (real/<name>/frames.npy ...), as shared_folder().
inline std::filesystem::path shared_recording(const std::string& name) {
  return shared_folder("real/" + name, "frames.npy");
}

// Whether `text` holds `part`; a failed check shows both.
inline bool contains(const std::string& text, const std::string& part) {
  INFO("looking for '" << part << "' in: " << text);
  return text.find(part) != std::string::npos;
}

// A fresh, empty temporary folder removed at scope exit.
class TempDir {
 public:
  TempDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("bolo-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  static int& counter() {
    static int n = 0;
    return n;
  }
  std::filesystem::path path_;
};

}  // namespace bolo::test
