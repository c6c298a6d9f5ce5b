// raw:-: the frames as raw little-endian Y16 on the standard output, concatenated without headers
// (width x height x 2 bytes each), flushed after every frame: what GStreamer's rawvideoparse
// (format=gray16-le) and NumPy's frombuffer read.

#include <bit>
#include <cerrno>
#include <cstring>
#include <vector>

#include "bolo/hal/frame_sink.hpp"
#include "builtin_sinks.hpp"

namespace bolo::hal::detail {
namespace {

class RawSink final : public FrameSink {
 public:
  RawSink(std::string spec, std::ostream& out) : spec_(std::move(spec)), out_(out) {}

  void write(std::span<const std::uint16_t> frame, const rec::FrameRow&) override {
    const char* bytes = reinterpret_cast<const char*>(frame.data());
    if constexpr (std::endian::native == std::endian::big) {
      swapped_.resize(frame.size());
      for (std::size_t i = 0; i < frame.size(); ++i)
        swapped_[i] = static_cast<std::uint16_t>((frame[i] >> 8) | (frame[i] << 8));
      bytes = reinterpret_cast<const char*>(swapped_.data());
    }
    errno = 0;
    out_.write(bytes, static_cast<std::streamsize>(frame.size_bytes()));
    out_.flush();
    if (!out_) fail();
  }
  void finish() override {
    errno = 0;
    out_.flush();
    if (!out_) fail();
  }

 private:
  // A reader that closed the pipe gives EPIPE (SIGPIPE is ignored while `bolo run` runs).
  [[noreturn]] void fail() const {
    throw SinkError(spec_ + ": write to the standard output failed" +
                    (errno != 0 ? std::string(": ") + std::strerror(errno) : std::string()));
  }

  std::string spec_;
  std::ostream& out_;
  std::vector<std::uint16_t> swapped_;
};

}  // namespace

SinkBackend raw_sink() {
  // Built whole, not assigned field by field: GCC 12 warns (-Wrestrict, a false positive) on
  // assigning the one-character argument.
  return SinkBackend{
      .scheme = "raw",
      .argument = "-",
      .argument_help = "- (the standard output): raw:-",
      .summary = "raw little-endian Y16 frames, W x H x 2 bytes each, concatenated on stdout",
      .accepts = [](const std::string& argument) { return argument == "-"; },
      .open = [](const std::string& spec, const std::string&, const SinkSetup& setup) -> std::unique_ptr<FrameSink> {
        if (setup.standard_output == nullptr) throw SinkError(spec + ": no standard output to write to");
        return std::make_unique<RawSink>(spec, *setup.standard_output);
      }};
}

}  // namespace bolo::hal::detail
