// recording:DIR: the frames into a recording through the atomic rec::RecordingWriter; DIR appears
// at finish(), whole, or never.

#include "bolo/hal/frame_sink.hpp"
#include "builtin_sinks.hpp"

namespace bolo::hal::detail {
namespace {

class RecordingSink final : public FrameSink {
 public:
  RecordingSink(const std::filesystem::path& dir, const SinkSetup& setup)
      : writer_(dir, setup.info, {setup.overwrite}) {}
  void write(std::span<const std::uint16_t> frame, const rec::FrameRow& row) override { writer_.append(frame, row); }
  void add_file(const std::filesystem::path& relative, const std::string& contents) override {
    writer_.add_file(relative, contents);
  }
  void finish() override { writer_.commit(); }

 private:
  rec::RecordingWriter writer_;
};

}  // namespace

SinkBackend recording_sink() {
  SinkBackend b;
  b.scheme = "recording";
  b.argument = "DIR";
  b.argument_help = "a folder, e.g. recording:out/run";
  b.summary = "a recording in the shared format, written whole when the run ends (also on SIGINT)";
  b.open = [](const std::string&, const std::string& dir, const SinkSetup& setup) {
    return std::make_unique<RecordingSink>(dir, setup);
  };
  return b;
}

}  // namespace bolo::hal::detail
