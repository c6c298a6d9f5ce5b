#include "fuzz_support.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <system_error>

namespace bolo::fuzz {
namespace fs = std::filesystem;

void check_failed(const char* expression, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: fuzz property failed: %s\n", file, line, expression);
  std::fflush(stderr);
  std::abort();
}

std::uint32_t ByteReader::range(std::uint32_t lo, std::uint32_t hi) {
  if (hi <= lo) return lo;
  const std::uint64_t span = std::uint64_t{hi} - lo + 1;
  const std::uint32_t raw = span <= 256 ? u8() : span <= 65536 ? u16() : u32();
  return lo + static_cast<std::uint32_t>(raw % span);
}

std::span<const std::uint8_t> ByteReader::bytes(std::size_t n) {
  const std::size_t k = std::min(n, remaining());
  std::span<const std::uint8_t> out(data_ + pos_, k);
  pos_ += k;
  return out;
}

namespace {

constexpr std::string_view kPrefix = "bolo-fuzz-";

// Removes scratch folders of processes that have gone (crashed fuzzers never clean up).
void remove_stale(const fs::path& base) {
  std::error_code ec;
  for (fs::directory_iterator it(base, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.starts_with(kPrefix)) continue;
    char* tail = nullptr;
    const long pid = std::strtol(name.c_str() + kPrefix.size(), &tail, 10);
    if (pid <= 0 || *tail != '\0') continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    fs::remove_all(it->path(), ignored);
  }
}

struct Scratch {
  fs::path dir;
  Scratch() {
    std::error_code ec;
    fs::path base = "/dev/shm";
    if (!fs::is_directory(base, ec) || ::access(base.c_str(), W_OK) != 0)
      base = fs::temp_directory_path();
    remove_stale(base);
    dir = base / (std::string(kPrefix) + std::to_string(::getpid()));
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    if (ec) {
      std::fprintf(stderr, "fuzz: cannot create %s: %s\n", dir.c_str(), ec.message().c_str());
      std::abort();
    }
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

}  // namespace

const fs::path& scratch_dir() {
  static const Scratch scratch;
  return scratch.dir;
}

void write_file(const fs::path& file, std::span<const std::uint8_t> bytes) {
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (f == nullptr) {
    std::fprintf(stderr, "fuzz: cannot write %s: %s\n", file.c_str(), std::strerror(errno));
    std::abort();
  }
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) {
    std::fprintf(stderr, "fuzz: short write to %s\n", file.c_str());
    std::abort();
  }
  std::fclose(f);
}

void write_file(const fs::path& file, std::string_view text) {
  write_file(file, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

fs::path fresh_dir(std::string_view name) {
  const fs::path dir = scratch_dir() / name;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directory(dir, ec);
  if (ec) {
    std::fprintf(stderr, "fuzz: cannot create %s: %s\n", dir.c_str(), ec.message().c_str());
    std::abort();
  }
  return dir;
}

std::size_t split(std::span<const std::uint8_t> input, std::string_view separator,
                  std::span<std::span<const std::uint8_t>> parts) {
  if (parts.empty()) return 0;
  std::string_view rest(reinterpret_cast<const char*>(input.data()), input.size());
  std::size_t n = 0;
  while (n + 1 < parts.size()) {
    const std::size_t at = rest.find(separator);
    if (at == std::string_view::npos) break;
    parts[n++] = std::span(reinterpret_cast<const std::uint8_t*>(rest.data()), at);
    rest.remove_prefix(at + separator.size());
  }
  parts[n++] = std::span(reinterpret_cast<const std::uint8_t*>(rest.data()), rest.size());
  return n;
}

}  // namespace bolo::fuzz
