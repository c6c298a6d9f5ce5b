#include "bolo/diagnose/simulator_config.hpp"

#include <cctype>
#include <sstream>
#include <stdexcept>

namespace bolo::diag {
namespace {

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

[[noreturn]] void bad(const std::string& source, int line, const std::string& what) {
  throw std::runtime_error(source + ": line " + std::to_string(line) + ": " + what);
}

// One value: "quoted" (no escapes needed by the simulator's options) or a bare word/number.
std::string value_at(const std::string& text, std::size_t& i, const std::string& source, int line) {
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  if (i >= text.size()) bad(source, line, "missing value");
  if (text[i] == '"') {
    const std::size_t end = text.find('"', i + 1);
    if (end == std::string::npos) bad(source, line, "unterminated string");
    std::string v = text.substr(i + 1, end - i - 1);
    i = end + 1;
    return v;
  }
  std::size_t end = i;
  while (end < text.size() && text[end] != ',' && text[end] != ']' && !std::isspace(static_cast<unsigned char>(text[end]))) ++end;
  std::string v = text.substr(i, end - i);
  i = end;
  return v;
}

}  // namespace

std::vector<ConfigEntry> parse_simulator_config(const std::string& text, const std::string& source) {
  std::vector<ConfigEntry> entries;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    // A '#' outside quotes starts a comment.
    bool quoted = false;
    std::size_t cut = raw.size();
    for (std::size_t i = 0; i < raw.size(); ++i) {
      if (raw[i] == '"') quoted = !quoted;
      if (raw[i] == '#' && !quoted) { cut = i; break; }
    }
    const std::string content = trim(raw.substr(0, cut));
    if (content.empty()) continue;
    const std::size_t eq = content.find('=');
    if (eq == std::string::npos) bad(source, line, "expected `option = value`");
    ConfigEntry e;
    e.line = line;
    e.option = trim(content.substr(0, eq));
    if (e.option.empty()) bad(source, line, "no option name before '='");
    for (char c : e.option)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_')
        bad(source, line, "option '" + e.option + "': letters, digits, '-' and '_' only");
    const std::string rest = trim(content.substr(eq + 1));
    std::size_t i = 0;
    if (!rest.empty() && rest[0] == '[') {
      i = 1;
      for (;;) {
        while (i < rest.size() && std::isspace(static_cast<unsigned char>(rest[i]))) ++i;
        if (i < rest.size() && rest[i] == ']') { ++i; break; }
        e.values.push_back(value_at(rest, i, source, line));
        while (i < rest.size() && std::isspace(static_cast<unsigned char>(rest[i]))) ++i;
        if (i < rest.size() && rest[i] == ',') { ++i; continue; }
        if (i < rest.size() && rest[i] == ']') { ++i; break; }
        bad(source, line, "expected ',' or ']' in the list of " + e.option);
      }
      // `effect = []` would pass an option to bolo simulate with nothing after it.
      if (e.values.empty()) bad(source, line, "empty list: " + e.option + " needs at least one value");
    } else {
      e.values.push_back(value_at(rest, i, source, line));
    }
    if (!trim(rest.substr(std::min(i, rest.size()))).empty()) bad(source, line, "unexpected text after the value of " + e.option);
    entries.push_back(std::move(e));
  }
  return entries;
}

}  // namespace bolo::diag
