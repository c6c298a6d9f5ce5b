// recording.json: what the recording is. Unknown keys are kept in RecordingInfo::extra.

#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <string_view>

#include "bolo/recording/recording.hpp"
#include "detail.hpp"

namespace bolo::rec {
namespace {

using detail::fail;
using nlohmann::json;

constexpr std::string_view kFormat = "bolo-recording";
constexpr int kVersion = 1;
constexpr std::array<std::string_view, 10> kKnownKeys = {
    "format", "version", "sensor", "width", "height", "bits", "fps", "units", "source", "notes"};

bool is_known(const std::string& key) {
  for (std::string_view known : kKnownKeys)
    if (key == known) return true;
  return false;
}

[[noreturn]] void fail_field(const std::filesystem::path& file, std::string_view field,
                             const std::string& what) {
  fail(file, "field " + std::string(field) + ": " + what);
}

std::string shown(const json& value) {
  std::string text = value.dump();
  if (text.size() > 60) text = text.substr(0, 60) + "...";
  return text;
}

// A JSON number with an integral value in [min, max] (160 and 160.0 both count).
std::uint64_t integer_field(const std::filesystem::path& file, const json& value,
                            std::string_view field, std::uint64_t min, std::uint64_t max) {
  const std::string range = "an integer from " + std::to_string(min) + " to " + std::to_string(max);
  if (value.is_number_unsigned()) {
    const auto v = value.get<std::uint64_t>();
    if (v >= min && v <= max) return v;
  } else if (value.is_number_integer()) {
    const auto v = value.get<std::int64_t>();
    if (v >= 0 && static_cast<std::uint64_t>(v) >= min && static_cast<std::uint64_t>(v) <= max)
      return static_cast<std::uint64_t>(v);
  } else if (value.is_number_float()) {
    const auto v = value.get<double>();
    if (std::isfinite(v) && v == std::floor(v) && v >= static_cast<double>(min) &&
        v <= static_cast<double>(max))
      return static_cast<std::uint64_t>(v);
  }
  fail_field(file, field, shown(value) + ", expected " + range);
}

std::string string_field(const std::filesystem::path& file, const json& j, std::string_view field) {
  const auto it = j.find(std::string(field));
  if (it == j.end() || it->is_null()) return {};
  if (!it->is_string()) fail_field(file, field, shown(*it) + ", expected a string");
  return it->get<std::string>();
}

Units parse_units(const std::filesystem::path& file, const std::string& text) {
  if (text == "counts") return Units::counts;
  if (text == "centikelvin") return Units::centikelvin;
  if (text == "counts8") return Units::counts8;
  fail_field(file, "units", "'" + text + "', expected counts, centikelvin or counts8");
}

// For a JSON error at `pos` in `text`: the key whose value starts there, if it can be found.
std::string key_before(std::string_view text, std::size_t pos) {
  auto skip_ws_back = [&](std::size_t& p) {
    while (p > 0 && std::isspace(static_cast<unsigned char>(text[p - 1]))) --p;
  };
  std::size_t p = std::min(pos, text.size());
  skip_ws_back(p);
  if (p == 0 || text[p - 1] != ':') return {};
  --p;
  skip_ws_back(p);
  if (p == 0 || text[p - 1] != '"') return {};
  const std::size_t end = p - 1;
  const std::size_t start = text.rfind('"', end == 0 ? 0 : end - 1);
  if (start == std::string_view::npos || start >= end) return {};
  return std::string(text.substr(start + 1, end - start - 1));
}

std::string strip_exception_prefix(std::string what) {
  // "[json.exception.parse_error.101] parse error at ..." -> "parse error at ..."
  if (!what.empty() && what.front() == '[') {
    const std::size_t close = what.find("] ");
    if (close != std::string::npos) what.erase(0, close + 2);
  }
  for (char& c : what)
    if (c == '\n' || c == '\r') c = ' ';
  return what;
}

}  // namespace

std::string to_string(Units units) {
  switch (units) {
    case Units::counts: return "counts";
    case Units::centikelvin: return "centikelvin";
    case Units::counts8: return "counts8";
  }
  return "counts";
}

nlohmann::json detail::parse_json_file(const std::filesystem::path& file) {
  const std::string text = read_text_file(file);
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // NaN / Infinity (as Python's json module writes them) are not JSON; name the key.
    std::size_t start = e.byte > 0 ? e.byte - 1 : 0;
    if (start > 0 && start <= text.size() && text[start - 1] == '-') --start;
    if (start < text.size()) {
      std::string word;
      for (std::size_t i = start; i < text.size() && (std::isalpha(static_cast<unsigned char>(text[i])) ||
                                                      (i == start && text[i] == '-'));
           ++i)
        word += text[i];
      if (word == "NaN" || word == "Infinity" || word == "-Infinity" || word == "nan" ||
          word == "inf" || word == "-inf") {
        const std::string key = key_before(text, start);
        fail(file, (key.empty() ? std::string() : "field " + key + ": ") + word +
                       " is not a finite number (JSON has no NaN/Infinity; use null for unknown)");
      }
    }
    fail(file, "invalid JSON: " + strip_exception_prefix(e.what()));
  } catch (const json::out_of_range& e) {
    // "number overflow parsing '1e999'": find the literal to name its key.
    const std::string what = e.what();
    const std::size_t open = what.find('\'');
    const std::size_t close = what.rfind('\'');
    if (open != std::string::npos && close > open) {
      const std::string literal = what.substr(open + 1, close - open - 1);
      const std::size_t at = text.find(literal);
      const std::string key = at == std::string::npos ? std::string() : key_before(text, at);
      if (!key.empty()) fail(file, "field " + key + ": number out of range (" + literal + ")");
    }
    fail(file, "invalid JSON: " + strip_exception_prefix(what));
  } catch (const json::exception& e) {
    fail(file, "invalid JSON: " + strip_exception_prefix(e.what()));
  }
}

RecordingInfo read_recording_json(const std::filesystem::path& file) {
  const json j = detail::parse_json_file(file);
  if (!j.is_object()) fail(file, "expected a JSON object, got " + shown(j));

  auto require = [&](std::string_view key) -> const json& {
    const auto it = j.find(std::string(key));
    if (it == j.end() || it->is_null()) fail_field(file, key, "missing");
    return *it;
  };

  const json& format = require("format");
  if (!format.is_string() || format.get<std::string>() != kFormat)
    fail_field(file, "format", shown(format) + ", expected \"" + std::string(kFormat) + "\"");
  const json& version = require("version");
  if (!version.is_number() || !(version.get<double>() == kVersion))
    fail_field(file, "version", shown(version) + " is not supported (expected " +
                                    std::to_string(kVersion) + ")");

  RecordingInfo info;
  constexpr std::uint64_t kMaxSide = std::numeric_limits<std::uint32_t>::max();
  info.width = static_cast<std::uint32_t>(integer_field(file, require("width"), "width", 1, kMaxSide));
  info.height =
      static_cast<std::uint32_t>(integer_field(file, require("height"), "height", 1, kMaxSide));
  if (const auto it = j.find("bits"); it != j.end() && !it->is_null())
    info.bits = static_cast<std::uint32_t>(integer_field(file, *it, "bits", 1, 32));
  if (const auto it = j.find("fps"); it != j.end() && !it->is_null()) {
    if (!it->is_number()) fail_field(file, "fps", shown(*it) + ", expected a number");
    const double fps = it->get<double>();
    if (!std::isfinite(fps)) fail_field(file, "fps", "not finite");
    if (!(fps > 0)) fail_field(file, "fps", detail::format_double(fps) + ", expected > 0");
    info.fps = fps;
  }
  if (const auto it = j.find("units"); it != j.end() && !it->is_null()) {
    if (!it->is_string()) fail_field(file, "units", shown(*it) + ", expected a string");
    info.units = parse_units(file, it->get<std::string>());
  }
  info.sensor = string_field(file, j, "sensor");
  info.source = string_field(file, j, "source");
  info.notes = string_field(file, j, "notes");
  for (const auto& [key, value] : j.items())
    if (!is_known(key)) info.extra[key] = value;
  return info;
}

void detail::validate_info(const std::filesystem::path& file, const RecordingInfo& info) {
  if (info.width == 0) fail_field(file, "width", "0, expected a positive integer");
  if (info.height == 0) fail_field(file, "height", "0, expected a positive integer");
  if (info.bits == 0 || info.bits > 32)
    fail_field(file, "bits", std::to_string(info.bits) + ", expected an integer from 1 to 32");
  if (info.fps && !std::isfinite(*info.fps)) fail_field(file, "fps", "not finite");
  if (info.fps && !(*info.fps > 0))
    fail_field(file, "fps", detail::format_double(*info.fps) + ", expected > 0");
  if (!info.extra.is_null() && !info.extra.is_object())
    fail_field(file, "extra", "must be a JSON object, got " + shown(info.extra));
}

void write_recording_json(const std::filesystem::path& file, const RecordingInfo& info) {
  detail::validate_info(file, info);
  nlohmann::ordered_json out;
  out["format"] = kFormat;
  out["version"] = kVersion;
  out["sensor"] = info.sensor;
  out["width"] = info.width;
  out["height"] = info.height;
  out["bits"] = info.bits;
  if (info.fps) out["fps"] = *info.fps;
  out["units"] = to_string(info.units);
  out["source"] = info.source;
  out["notes"] = info.notes;
  if (info.extra.is_object())
    for (const auto& [key, value] : info.extra.items())
      if (!is_known(key)) out[key] = value;
  std::string text;
  try {
    text = out.dump(2);
  } catch (const json::exception& e) {
    fail(file, "cannot write JSON: " + strip_exception_prefix(e.what()));
  }
  text += '\n';
  write_file_atomically(file, text);
}

}  // namespace bolo::rec
