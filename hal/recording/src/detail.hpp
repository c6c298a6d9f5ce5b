#pragma once
// Private helpers shared by the bolo::rec sources.

#include <bit>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bolo/recording/recording.hpp"

namespace bolo::rec::detail {

// Throws Error("<file>: <what>").
[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what);
// Throws Error("<file>: frame <frame>: field <field>: <what>"); empty field: no "field" part.
[[noreturn]] void fail_frame(const std::filesystem::path& file, std::uint64_t frame,
                             std::string_view field, const std::string& what);

// Shortest text that reads back to the same double ("0.1", "1e-07", "nan", "inf").
std::string format_double(double value);
// "(10, 60, 80)", as NumPy prints a shape.
std::string shape_string(const std::vector<std::uint64_t>& shape);
// "120x160" (height x width, the order of a NumPy shape).
std::string size_string(std::uint64_t height, std::uint64_t width);

// Whole file as bytes; Error naming the file when it cannot be read.
std::string read_text_file(const std::filesystem::path& file);
// A fresh, unused sibling path ".<name>.<tag>-<pid>-<n>" of `path` (not created).
std::filesystem::path temp_sibling(const std::filesystem::path& path, std::string_view tag);

// Checks a FrameRow sequence as frames.csv requires: index == row number, finite numbers,
// strictly increasing t_s (among known values), non-negative exposure/readout.
class RowValidator {
 public:
  explicit RowValidator(std::filesystem::path file) : file_(std::move(file)) {}
  // `t_text`: the t_s cell as written (for messages), empty to print the value.
  void check(const FrameRow& row, std::uint64_t number, std::string_view t_text = {});
  // Continues after rows already checked: the last known t_s.
  void seed(double last_t) {
    last_t_ = last_t;
    last_t_text_ = format_double(last_t);
  }

 private:
  std::filesystem::path file_;
  std::optional<double> last_t_;
  std::string last_t_text_;
};

// Parses a JSON file; syntax errors, NaN/Infinity literals and overflowing numbers become an
// Error naming the file (and the key, when it can be found).
nlohmann::json parse_json_file(const std::filesystem::path& file);

// Validates what write_recording_json would write; `file` names the messages.
void validate_info(const std::filesystem::path& file, const RecordingInfo& info);

inline constexpr bool kBigEndianHost = std::endian::native == std::endian::big;

inline std::uint16_t byteswap16(std::uint16_t v) {
  return static_cast<std::uint16_t>((v >> 8) | (v << 8));
}
inline std::uint32_t byteswap32(std::uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0x0000ff00u) | ((v << 8) & 0x00ff0000u) | (v << 24);
}

}  // namespace bolo::rec::detail
