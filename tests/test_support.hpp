#pragma once
// Helpers shared by the test binaries.

#include <filesystem>
#include <string>

#include <unistd.h>

#include <catch2/catch.hpp>

namespace bolo::test {

// Folder of a shared real recording, or an empty path (and a Catch2 warning) when ../shared is
// absent, so the caller can skip: `auto dir = shared_recording("lepton3-possum"); if (dir.empty()) return;`
inline std::filesystem::path shared_recording(const std::string& name) {
  std::filesystem::path dir = std::filesystem::path(BOLO_SHARED_DATA) / "real" / name;
  if (!std::filesystem::exists(dir / "frames.npy")) {
    WARN("skipped: shared recording " << dir.string()
                                      << " is absent (../shared/data not beside the checkout)");
    return {};
  }
  return dir;
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
