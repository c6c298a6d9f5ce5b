#pragma once
// Where whole frames go, by name, as sources come by name (source_registry.hpp):
// open_sink("recording:out/run", setup). Built-in sinks: a recording (atomic, committed at
// finish()), raw little-endian Y16 frames on stdout, a V4L2 output device (v4l2loopback). Host
// code: every error is a SinkError whose message starts with the spec.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "bolo/recording/recording.hpp"

namespace bolo::hal {

class SinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What a sink is opened for.
struct SinkSetup {
  rec::RecordingInfo info;    // width, height for every sink; all of it for a recording's recording.json
  bool overwrite = false;     // a recording may replace an existing recording (or empty folder)
  std::ostream* standard_output = nullptr;  // what raw:- writes to (the command's stdout)
};

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // One frame of info.width x info.height pixels, row-major, with its frames.csv row. Throws
  // SinkError naming the sink when it cannot take it.
  virtual void write(std::span<const std::uint16_t> frame, const rec::FrameRow& row) = 0;
  // A file beside the frames (capture.json); only a recording keeps one.
  virtual void add_file(const std::filesystem::path& /*relative*/, const std::string& /*contents*/) {}
  // After the last frame: a recording is committed (renamed into place; destroyed without it,
  // nothing is left), a stream flushed.
  virtual void finish() = 0;
};

struct SinkBackend {
  std::string scheme;         // "recording", "raw", "v4l2": the spec is SCHEME:ARG
  std::string argument;       // shown in help and errors, e.g. "DIR", "-", "/dev/videoN"
  std::string argument_help;  // what the argument must be, e.g. "a folder, e.g. recording:out/run"
  std::string summary;        // one line for --help
  // Whether the backend takes this (non-empty) argument; a spec is refused with argument_help otherwise.
  std::function<bool(const std::string& argument)> accepts;
  // Opens the sink; throws SinkError starting with `spec` (or rec::Error naming the folder).
  std::function<std::unique_ptr<FrameSink>(const std::string& spec, const std::string& argument,
                                           const SinkSetup& setup)>
      open;

  std::string example() const { return scheme + ":" + argument; }
};

struct SinkSpec {
  SinkBackend backend;
  std::string argument;
};

// The built-in sinks, in order.
std::vector<SinkBackend> sink_schemes();
// Which sink a spec names, and its argument; throws SinkError for an unknown or malformed spec
// (before anything is opened).
SinkSpec parse_sink_spec(std::string_view spec);
// Opens the sink a spec names for frames of setup.info's size. Throws SinkError ("SPEC: reason");
// a recording's own errors (rec::Error) pass unchanged, as they name its folder.
std::unique_ptr<FrameSink> open_sink(std::string_view spec, const SinkSetup& setup);

}  // namespace bolo::hal
