#include "detail.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <unistd.h>

namespace bolo::rec::detail {

void fail(const std::filesystem::path& file, const std::string& what) {
  throw Error(file.string() + ": " + what);
}

void fail_frame(const std::filesystem::path& file, std::uint64_t frame, std::string_view field,
                const std::string& what) {
  std::string message = file.string() + ": frame " + std::to_string(frame) + ": ";
  if (!field.empty()) {
    message += "field ";
    message += field;
    message += ": ";
  }
  message += what;
  throw Error(message);
}

std::string format_double(double value) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string shape_string(const std::vector<std::uint64_t>& shape) {
  std::string text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(shape[i]);
  }
  if (shape.size() == 1) text += ",";
  return text + ")";
}

std::string size_string(std::uint64_t height, std::uint64_t width) {
  return std::to_string(height) + "x" + std::to_string(width);
}

std::string read_text_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) fail(file, "read failed");
  return std::move(contents).str();
}

std::filesystem::path temp_sibling(const std::filesystem::path& path, std::string_view tag) {
  static std::atomic<unsigned long> counter{0};
  const std::filesystem::path parent = path.parent_path();
  std::string base = ".";
  base += path.filename().string();
  base += '.';
  base += tag;
  base += '-';
  base += std::to_string(::getpid());
  base += '-';
  for (;;) {
    std::filesystem::path candidate = parent / (base + std::to_string(counter++));
    std::error_code ec;
    if (!std::filesystem::exists(std::filesystem::symlink_status(candidate, ec))) return candidate;
  }
}

void RowValidator::check(const FrameRow& row, std::uint64_t number, std::string_view t_text) {
  if (row.index != number)
    fail_frame(file_, number, "index",
               std::to_string(row.index) + ", expected " + std::to_string(number) +
                   " (index must equal the row number)");
  auto finite = [&](const std::optional<double>& value, std::string_view field) {
    if (value && !std::isfinite(*value))
      fail_frame(file_, number, field, "not finite (" + format_double(*value) + ")");
  };
  finite(row.t_s, "t_s");
  finite(row.exposure_s, "exposure_s");
  finite(row.readout_s, "readout_s");
  finite(row.fpa_temp_c, "fpa_temp_c");
  finite(row.housing_temp_c, "housing_temp_c");
  if (row.exposure_s && *row.exposure_s < 0)
    fail_frame(file_, number, "exposure_s", "negative (" + format_double(*row.exposure_s) + ")");
  if (row.readout_s && *row.readout_s < 0)
    fail_frame(file_, number, "readout_s", "negative (" + format_double(*row.readout_s) + ")");
  if (row.t_s) {
    const std::string text = t_text.empty() ? format_double(*row.t_s) : std::string(t_text);
    if (last_t_ && !(*row.t_s > *last_t_))
      fail_frame(file_, number, "t_s", "not monotonic (" + text + " after " + last_t_text_ + ")");
    last_t_ = row.t_s;
    last_t_text_ = text;
  }
}

}  // namespace bolo::rec::detail
