#include "bolo/hal/source_registry.hpp"

#include <algorithm>
#include <cctype>
#include <mutex>

#include "bolo/recording/recording.hpp"
#include "builtin_sources.hpp"

namespace bolo::hal {
namespace {

struct Registry {
  std::mutex mutex;
  std::vector<SourceBackend> backends;
  Registry() {
    detail::add_device_sources(backends);
    detail::add_recording_sources(backends);
    detail::add_replay_sources(backends);
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

[[noreturn]] void spec_error(std::string_view spec, const std::string& reason) {
  throw SourceError(std::string(spec) + ": " + reason);
}

// "a, b, c or d" (last = " or "), "a, b, c, d" (last = ", ")
std::string listing(const std::vector<std::string>& items, const char* last) {
  std::string text;
  for (std::size_t i = 0; i < items.size(); ++i)
    text += (i == 0 ? "" : i + 1 == items.size() ? last : ", ") + items[i];
  return text;
}

}  // namespace

void register_source(SourceBackend backend) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto same = std::find_if(r.backends.begin(), r.backends.end(),
                                 [&](const SourceBackend& b) { return b.scheme == backend.scheme; });
  if (same != r.backends.end())
    *same = std::move(backend);
  else
    r.backends.push_back(std::move(backend));
}

std::vector<SourceBackend> source_schemes() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  return r.backends;
}

SourceSpec parse_source_spec(std::string_view spec, const SourceOptions& options) {
  const std::vector<SourceBackend> backends = source_schemes();
  for (const SourceBackend& b : backends) {
    if (b.argument.empty()) {
      if (spec == b.scheme) return {b, {}};
      continue;
    }
    if (spec.substr(0, b.scheme.size() + 1) != b.scheme + ":") continue;
    const std::string argument(spec.substr(b.scheme.size() + 1));
    if (argument.empty()) spec_error(spec, b.scheme + ": needs " + b.argument_help);
    if (b.check) {
      try {
        b.check(argument);
      } catch (const std::invalid_argument& e) {
        spec_error(spec, e.what());
      }
    }
    return {b, argument};
  }
  const std::size_t colon = spec.find(':');
  const std::string prefix(spec.substr(0, colon));
  // usb:boson: a family of whole-spec schemes (usb:flirone, usb:seek) that has no such member.
  std::vector<std::string> family;
  for (const SourceBackend& b : backends)
    if (b.argument.empty() && colon != std::string_view::npos && b.scheme.rfind(prefix + ":", 0) == 0)
      family.push_back(b.scheme);
  if (!family.empty()) {
    std::string upper = prefix;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    spec_error(spec, "unknown " + upper + " camera '" + std::string(spec.substr(colon + 1)) + "' (known: " +
                         listing(family, ", ") + ")");
  }
  const bool path_like = colon == std::string_view::npos || prefix.find('/') != std::string::npos;
  if (options.bare_path_is_recording && path_like && !spec.empty()) {
    for (const SourceBackend& b : backends)
      if (b.scheme == "file") return {b, std::string(spec)};
  }
  std::vector<std::string> examples;
  examples.reserve(backends.size());
  for (const SourceBackend& b : backends) examples.push_back(b.example());
  spec_error(spec, "unknown device (expected " + listing(examples, " or ") + ")");
}

std::unique_ptr<OpenedSource> open_source(std::string_view spec, const SourceOptions& options) {
  const SourceSpec parsed = parse_source_spec(spec, options);
  if (!parsed.backend.unavailable.empty()) spec_error(spec, parsed.backend.unavailable);
  try {
    return parsed.backend.open(parsed.argument, options);
  } catch (const SourceError&) {
    throw;
  } catch (const rec::Error&) {
    throw;
  } catch (const std::exception& e) {
    spec_error(spec, e.what());
  }
}

std::filesystem::path recording_folder_of(std::string_view spec, std::string_view command) {
  const SourceSpec parsed = parse_source_spec(spec);
  if (parsed.backend.scheme != "file")
    throw SourceError(std::string(spec) + ": bolo " + std::string(command) +
                      " takes a recording (a folder or file:REC); record " + parsed.backend.scheme +
                      " with `bolo capture` first");
  require_recording_folder(parsed.argument);
  return parsed.argument;
}

void require_recording_folder(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) throw SourceError(dir.string() + ": no such recording folder");
  if (!std::filesystem::is_directory(dir, ec))
    throw SourceError(dir.string() +
                      ": not a folder (a recording is a folder with recording.json, frames.npy, frames.csv)");
}

}  // namespace bolo::hal
