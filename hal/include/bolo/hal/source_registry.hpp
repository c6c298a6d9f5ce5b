#pragma once
// Frame sources by name: open_source("v4l2:/dev/video0") finds the backend registered for the
// spec's scheme and opens it. The built-in backends (hal/src/sources_*.cpp) are added by the
// registry itself on first use, so linking it from a static library cannot drop them; others
// (a test's, a tool's) add themselves with register_source. Host code: every error is a
// SourceError whose message starts with the spec.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "bolo/core/frame_source.hpp"

namespace bolo::hal {

class SourceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SourceOptions {
  // A spec without a scheme ("rec", "data/run-3") names a recording folder, as file: does.
  bool bare_path_is_recording = true;
};

// A source opened by name: the backend's source with whatever it runs on (a USB transport, a
// transfer log) kept alive beside it, and what a recording of it should say about the sensor.
class OpenedSource final : public FrameSource {
 public:
  OpenedSource(std::unique_ptr<FrameSource> source, std::string sensor,
               std::shared_ptr<void> resources = {}, std::function<bool()> shutter = {})
      : resources_(std::move(resources)), source_(std::move(source)), sensor_(std::move(sensor)),
        shutter_(std::move(shutter)) {}
  SourceFormat format() const override { return source_->format(); }
  StreamStatus stream_frame(fw::LineSink& sink) override { return source_->stream_frame(sink); }
  SourceStats stats() const override { return source_->stats(); }
  ExtraCounters extra_counters() const override { return source_->extra_counters(); }

  const std::string& sensor() const { return sensor_; }
  // The backend's own source, for what only that kind offers (a RecordingPlayer's recording).
  FrameSource& backend() { return *source_; }
  const FrameSource& backend() const { return *source_; }
  bool has_shutter() const { return static_cast<bool>(shutter_); }
  // Asks the device for a shutter (FFC) event; false when it has no such command or refused.
  bool request_shutter() { return shutter_ && shutter_(); }

 private:
  std::shared_ptr<void> resources_;  // declared first: outlives the source that uses it
  std::unique_ptr<FrameSource> source_;
  std::string sensor_;
  std::function<bool()> shutter_;
};

struct SourceBackend {
  // "v4l2" takes an argument (v4l2:ARG); "usb:seek", with `argument` empty, is the whole spec.
  std::string scheme;
  std::string argument;       // shown in help and errors, e.g. "/dev/videoN", "REC"
  std::string argument_help;  // what a missing argument needs, e.g. "a device node, e.g. v4l2:/dev/video0"
  std::string summary;        // one line for --help and `bolo devices`
  bool finite = false;        // ends by itself (a recording, a log) instead of streaming on
  bool shutter = false;       // has its own shutter (FFC) command
  std::string unavailable;    // why this build cannot open it; empty when it can
  // Checks the argument's options without opening anything (throws std::invalid_argument); may be empty.
  std::function<void(const std::string& argument)> check;
  std::function<std::unique_ptr<OpenedSource>(const std::string& argument, const SourceOptions&)> open;

  // How the spec is written: "v4l2:/dev/videoN", "usb:seek".
  std::string example() const { return argument.empty() ? scheme : scheme + ":" + argument; }
};

struct SourceSpec {
  SourceBackend backend;
  std::string argument;
};

// Adds a backend, or replaces the one registered for the same scheme.
void register_source(SourceBackend backend);
// The registered backends, in registration order (built-ins first).
std::vector<SourceBackend> source_schemes();
// Which backend a spec names, and its argument; throws SourceError for an unknown or malformed spec.
SourceSpec parse_source_spec(std::string_view spec, const SourceOptions& options = {});
// Opens the source a spec names. Throws SourceError ("SPEC: reason"); a recording's own errors
// (rec::Error) pass unchanged, as they name the recording's file, frame and field already.
std::unique_ptr<OpenedSource> open_source(std::string_view spec, const SourceOptions& options = {});
// The recording folder a spec names (a bare folder or file:REC), for a command that reads a whole
// recording (`command` is named in the refusal). Throws SourceError for another kind of source, a
// missing folder or a path that is not a folder.
std::filesystem::path recording_folder_of(std::string_view spec, std::string_view command);
// Throws SourceError unless `dir` exists and is a folder (what every recording is).
void require_recording_folder(const std::filesystem::path& dir);

}  // namespace bolo::hal
