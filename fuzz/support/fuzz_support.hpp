#pragma once
// Shared by the fuzz targets (fuzz/targets/*.cpp): a byte reader that turns fuzz input into
// structured choices, a per-process scratch folder on tmpfs for the parsers that take paths, and
// the check that turns a broken property into a crash the fuzzer (or the replay) reports.
//
// A target defines LLVMFuzzerTestOneInput and nothing else; it is linked either with libFuzzer
// (fuzz_<name>) or with replay_main.cpp (fuzz_<name>_replay, any compiler).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

namespace bolo::fuzz {

// A property the code under test must keep. On failure prints the message and aborts, which
// libFuzzer records as a crash and the replay executable as a failed test.
[[noreturn]] void check_failed(const char* expression, const char* file, int line);
#define BOLO_FUZZ_CHECK(cond) \
  ((cond) ? static_cast<void>(0) : ::bolo::fuzz::check_failed(#cond, __FILE__, __LINE__))

// Reads the fuzz input front to back; past its end every read gives zeros (so a short input is
// still a valid, small test case).
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::size_t remaining() const { return size_ - pos_; }
  bool empty() const { return pos_ >= size_; }

  std::uint8_t u8() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint16_t u16() { return static_cast<std::uint16_t>(u8() | (u8() << 8)); }
  std::uint32_t u32() { return u16() | (std::uint32_t{u16()} << 16); }
  std::uint64_t u64() { return u32() | (std::uint64_t{u32()} << 32); }
  bool flag() { return (u8() & 1) != 0; }
  // A value in [lo, hi] from one or two bytes.
  std::uint32_t range(std::uint32_t lo, std::uint32_t hi);
  // The next `n` bytes (fewer at the end of the input).
  std::span<const std::uint8_t> bytes(std::size_t n);
  std::span<const std::uint8_t> rest() { return bytes(remaining()); }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Small deterministic generator for bulk data (tables, pixels) seeded from a few input bytes,
// so the fuzzer steers the shape of a test without spelling out every pixel.
class Prng {
 public:
  explicit Prng(std::uint64_t seed) : s_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  std::uint64_t next() {
    s_ ^= s_ << 13;
    s_ ^= s_ >> 7;
    s_ ^= s_ << 17;
    return s_;
  }

 private:
  std::uint64_t s_;
};

// This process's scratch folder (tmpfs /dev/shm when present), created on first use and
// removed at exit; folders left behind by processes that no longer exist are removed too.
const std::filesystem::path& scratch_dir();
// Writes `bytes` to `file` (truncating).
void write_file(const std::filesystem::path& file, std::span<const std::uint8_t> bytes);
void write_file(const std::filesystem::path& file, std::string_view text);
// An empty folder `name` inside scratch_dir() (emptied if it exists).
std::filesystem::path fresh_dir(std::string_view name);

// Splits `input` at every occurrence of `separator` (at most `max_parts` parts; the last part
// keeps any further separators).
std::size_t split(std::span<const std::uint8_t> input, std::string_view separator,
                  std::span<std::span<const std::uint8_t>> parts);

}  // namespace bolo::fuzz
