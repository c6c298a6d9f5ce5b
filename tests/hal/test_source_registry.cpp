// hal::open_source: every built-in scheme parses, bad specs are refused naming the spec, a
// recording opens and streams, and a backend registered here is found by name.

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "bolo/core/frame_collector.hpp"
#include "bolo/hal/device_spec.hpp"
#include "bolo/hal/recording_player.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/recording/recording.hpp"
#include "../test_support.hpp"

using namespace bolo;
namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t kWidth = 8, kHeight = 6, kFrames = 5;

void write_recording(const fs::path& dir) {
  rec::RecordingInfo info;
  info.sensor = "registry test sensor";
  info.width = kWidth;
  info.height = kHeight;
  info.bits = 14;
  rec::RecordingWriter writer(dir, info);
  for (std::uint64_t i = 0; i < kFrames; ++i) {
    std::vector<std::uint16_t> pixels(std::size_t{kWidth} * kHeight, static_cast<std::uint16_t>(1000 + i));
    rec::FrameRow row;
    row.index = i;
    row.t_s = 0.1 * static_cast<double>(i);
    writer.append(pixels, row);
  }
  writer.commit();
}

std::string refusal(const std::string& spec, const hal::SourceOptions& options = {}) {
  try {
    hal::parse_source_spec(spec, options);
  } catch (const hal::SourceError& e) {
    return e.what();
  }
  return "(accepted)";
}

// Counts the frames a source streams until it ends.
std::uint64_t stream_all(hal::FrameSource& source) {
  const hal::SourceFormat f = source.format();
  std::vector<fw::Pixel> storage(fw::FrameCollector::storage_pixels(f.width, f.height));
  fw::FrameCollector frame(f.width, f.height, storage);
  std::uint64_t n = 0;
  while (source.stream_frame(frame) == hal::StreamStatus::frame) {
    REQUIRE(frame.complete());
    CHECK(frame.pixels()[0] == 1000 + n);
    ++n;
  }
  return n;
}

// A source of `frames` constant frames, to register from the test.
class CountingSource final : public hal::FrameSource {
 public:
  explicit CountingSource(std::uint64_t frames) : frames_(frames) {}
  hal::SourceFormat format() const override { return {.width = 4, .height = 2}; }
  hal::StreamStatus stream_frame(fw::LineSink& sink) override {
    if (stats_.frames_delivered == frames_) return hal::StreamStatus::end_of_stream;
    const std::vector<fw::Pixel> line(4, static_cast<fw::Pixel>(1000 + stats_.frames_delivered));
    fw::FrameHeader h;
    h.width = 4;
    h.height = 2;
    sink.begin_frame(h);
    for (std::uint32_t row = 0; row < 2; ++row) sink.push_line(row, fw::LineView(line.data(), line.size()));
    sink.end_frame();
    ++stats_.frames_delivered;
    return hal::StreamStatus::frame;
  }
  hal::SourceStats stats() const override { return stats_; }

 private:
  std::uint64_t frames_;
  hal::SourceStats stats_;
};

}  // namespace

TEST_CASE("source registry: every built-in scheme parses, in the order the help lists them", "[hal][sources]") {
  std::vector<std::string> examples;
  for (const hal::SourceBackend& b : hal::source_schemes()) {
    examples.push_back(b.example());
    const std::string spec = b.argument.empty() ? b.scheme : b.scheme + ":x";
    const hal::SourceSpec parsed = hal::parse_source_spec(spec);
    CHECK(parsed.backend.scheme == b.scheme);
    CHECK(parsed.argument == (b.argument.empty() ? "" : "x"));
    CHECK_FALSE(b.summary.empty());
    CHECK(static_cast<bool>(b.open) == b.unavailable.empty());
  }
  const std::vector<std::string> builtin = {"v4l2:/dev/videoN", "usb:flirone", "usb:seek", "file:REC",
                                            "flirone-log:DIR"};
  REQUIRE(examples.size() >= builtin.size());
  CHECK(std::vector<std::string>(examples.begin(), examples.begin() + 5) == builtin);
  CHECK(hal::parse_source_spec("v4l2:/dev/video3").argument == "/dev/video3");
  CHECK(hal::parse_source_spec("file:a:b").argument == "a:b");
  // A bare path names a recording folder, unless the caller wants a scheme.
  CHECK(hal::parse_source_spec("data/run-3").backend.scheme == "file");
  CHECK(hal::parse_source_spec("./odd:name").argument == "./odd:name");
  CHECK(hal::parse_source_spec("usb:seek").backend.shutter);
  CHECK(hal::parse_source_spec("file:rec").backend.finite);
  CHECK_FALSE(hal::parse_source_spec("v4l2:/dev/video0").backend.finite);
}

TEST_CASE("source registry: unknown and malformed specs are refused naming the spec", "[hal][sources]") {
  const hal::SourceOptions scheme_only{.bare_path_is_recording = false};
  CHECK(refusal("webcam", scheme_only).rfind("webcam: unknown device (expected v4l2:/dev/videoN, usb:flirone, usb:seek, file:REC", 0) == 0);
  CHECK(refusal("rtsp://camera").rfind("rtsp://camera: unknown device (expected ", 0) == 0);
  CHECK(refusal("usb:boson") == "usb:boson: unknown USB camera 'boson' (known: usb:flirone, usb:seek)");
  CHECK(refusal("v4l2:") == "v4l2:: v4l2: needs a device node, e.g. v4l2:/dev/video0");
  CHECK(refusal("file:") == "file:: file: needs a recording folder, e.g. file:rec");
  CHECK(refusal("flirone-log:") == "flirone-log:: flirone-log: needs a transfer-log folder");
  // v4l2:NODE?KEY=VALUE: the options are checked by the parse, before the node is opened.
  CHECK(refusal("v4l2:/dev/null?format=RGB3") == "v4l2:/dev/null?format=RGB3: format=RGB3: expected Y16, GREY, YUYV or UYVY");
  CHECK(refusal("v4l2:/dev/null?fps=9") == "v4l2:/dev/null?fps=9: 'fps=9': expected format=Y16|GREY|YUYV|UYVY or "
                                             "gain=high|low|auto, radiometry=on|off, agc=on|off");
  CHECK(refusal("v4l2:/dev/null?format=grey") == "(accepted)");
  // A PureThermal's Lepton settings (device_spec.hpp), checked as words before anything opens.
  CHECK(refusal("v4l2:/dev/null?gain=low,radiometry=off,agc=on,format=Y16") == "(accepted)");
  CHECK(refusal("v4l2:/dev/null?gain=medium") == "v4l2:/dev/null?gain=medium: 'gain=medium': expected gain=high|low|auto");
  CHECK(refusal("v4l2:/dev/null?agc=1") == "v4l2:/dev/null?agc=1: 'agc=1': expected agc=off|on");
  CHECK(refusal("", scheme_only).rfind(": unknown device", 0) == 0);
  // Opening: the backend's reason after the spec.
  try {
    hal::open_source("v4l2:/dev/null");
    FAIL("v4l2:/dev/null opened");
  } catch (const hal::SourceError& e) {
    CHECK(std::string(e.what()).rfind("v4l2:/dev/null: /dev/null: ", 0) == 0);
  }
  try {
    hal::open_source("v4l2:/dev/null?format=GREY");
    FAIL("v4l2:/dev/null?format=GREY opened");
  } catch (const hal::SourceError& e) {
    CHECK(std::string(e.what()) == "v4l2:/dev/null?format=GREY: /dev/null: not a V4L2 device");
  }
  if (!hal::usb_backend_available())
    CHECK_THROWS_WITH(hal::open_source("usb:seek"), Catch::Contains("usb:seek: this build has no USB backend"));
}

TEST_CASE("source registry: a recording folder opens and streams, with and without file:", "[hal][sources]") {
  bolo::test::TempDir tmp;
  write_recording(tmp / "rec");
  for (const std::string spec : {"file:" + (tmp / "rec").string(), (tmp / "rec").string()}) {
    INFO(spec);
    const std::unique_ptr<hal::OpenedSource> source = hal::open_source(spec);
    CHECK(source->sensor() == "registry test sensor");
    CHECK(source->format().width == kWidth);
    CHECK(source->format().bits == 14);
    CHECK_FALSE(source->has_shutter());
    CHECK(dynamic_cast<hal::RecordingPlayer*>(&source->backend()) != nullptr);
    CHECK(stream_all(*source) == kFrames);
    CHECK(source->stats().frames_delivered == kFrames);
  }
  // A recording's own errors name its files, not the spec.
  CHECK_THROWS_AS(hal::open_source("file:" + (tmp / "none").string()), rec::Error);
}

TEST_CASE("source registry: a backend registered by a test is found by name", "[hal][sources]") {
  hal::SourceBackend counting;
  counting.scheme = "counting";
  counting.argument = "N";
  counting.argument_help = "a frame count";
  counting.summary = "N constant frames (test)";
  counting.finite = true;
  counting.open = [](const std::string& n, const hal::SourceOptions&) {
    if (n.find_first_not_of("0123456789") != std::string::npos) throw std::invalid_argument("not a count: " + n);
    return std::make_unique<hal::OpenedSource>(std::make_unique<CountingSource>(std::stoull(n)), "counting");
  };
  hal::register_source(counting);
  const std::vector<hal::SourceBackend> schemes = hal::source_schemes();
  CHECK(std::count_if(schemes.begin(), schemes.end(), [](const hal::SourceBackend& b) { return b.scheme == "counting"; }) == 1);
  const std::unique_ptr<hal::OpenedSource> source = hal::open_source("counting:3");
  CHECK(source->sensor() == "counting");
  std::vector<fw::Pixel> storage(fw::FrameCollector::storage_pixels(4, 2));
  fw::FrameCollector frame(4, 2, storage);
  std::uint64_t n = 0;
  while (source->stream_frame(frame) == hal::StreamStatus::frame) ++n;
  CHECK(n == 3);
  CHECK_THROWS_WITH(hal::open_source("counting:x"), "counting:x: not a count: x");
  // Registering the scheme again replaces it.
  counting.summary = "replaced";
  hal::register_source(counting);
  CHECK(hal::parse_source_spec("counting:1").backend.summary == "replaced");
}
