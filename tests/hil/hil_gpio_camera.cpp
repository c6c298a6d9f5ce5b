// The real-device GPIO check: a camera opened by its source spec (the HAL's own backend, as
// `bolo capture --device` opens it) with its GPIO lines beside it through GpiodLines and
// GpioSyncedSource. With a sync line: every frame matched to a pulse of its own within ~one frame
// period; with a shutter line: a pulse sent before frame N/2 marks exactly that frame as an FFC
// frame; an "FFC imminent" line is reported. Checks in gpio_camera_check.hpp.
//
//   hil_gpio_camera --device SPEC --gpio CHIP:sync=N,shutter=N,imminent=N [--frames N]

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "bolo/hal/device_spec.hpp"
#include "bolo/hal/gpio_lines.hpp"
#include "bolo/hal/gpio_synced_source.hpp"
#include "bolo/hal/source_registry.hpp"
#include "gpio_camera_check.hpp"

namespace {

using namespace bolo;

class HeaderSink final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& h) override { header = h; }
  void push_line(std::uint32_t, fw::LineView) override {}
  void end_frame() override {}
  fw::FrameHeader header;
};

}  // namespace

int main(int argc, char** argv) {
  std::string device, gpio;
  std::size_t frames = 300;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--device") device = argv[i + 1];
    else if (a == "--gpio") gpio = argv[i + 1];
    else if (a == "--frames") frames = std::stoul(argv[i + 1]);
    else {
      std::printf("hil_gpio_camera: FAIL unknown option %s\n", a.c_str());
      return 2;
    }
  }
  if (device.empty() || gpio.empty() || frames < 4) {
    std::printf("hil_gpio_camera: FAIL give --device SPEC --gpio CHIP:sync=N,shutter=N,imminent=N [--frames N >= 4]\n");
    return 2;
  }
  try {
    const hal::GpioConfig config = hal::parse_gpio_spec(gpio);
    hal::SourceOptions options;
    options.bare_path_is_recording = false;
    const auto camera = hal::open_source(device, options);
    hal::GpiodLines lines(config);
    hal::GpioSyncedSource synced(*camera, lines);
    bolo::hil::GpioCameraPlan plan;
    plan.sync = config.sync_line >= 0;
    std::vector<bolo::hil::GpioCameraFrame> seen;
    HeaderSink sink;
    std::size_t faults_in_a_row = 0;
    while (seen.size() < frames) {
      if (config.shutter_line >= 0 && !plan.shutter_before && seen.size() == frames / 2) {
        if (!synced.request_shutter()) throw std::runtime_error(gpio + ": the shutter line could not be pulsed");
        plan.shutter_before = seen.size();
      }
      const hal::StreamStatus s = synced.stream_frame(sink);
      if (s == hal::StreamStatus::end_of_stream) break;
      if (s == hal::StreamStatus::fault) {
        if (++faults_in_a_row > 50) throw std::runtime_error(device + ": more than 50 faults in a row");
        continue;
      }
      faults_in_a_row = 0;
      seen.push_back({sink.header.timestamp_ns, sink.header.timestamp_valid, synced.last_marks()});
    }
    const bolo::hil::GpioCameraResult r = bolo::hil::check_gpio_camera(seen, plan);
    for (const std::string& f : r.failures) std::printf("hil_gpio_camera: FAIL %s\n", f.c_str());
    std::printf("hil_gpio_camera: %s: %s with %s, %zu frames, frame interval %.2f ms, sync-to-frame latency median "
                "%.3f ms max %.3f ms, frames after our shutter pulse %zu, FFC imminent frames %zu\n",
                r.failures.empty() ? "PASS" : "FAIL", device.c_str(), gpio.c_str(), seen.size(),
                static_cast<double>(r.median_interval_ns) / 1e6, static_cast<double>(r.median_latency_ns) / 1e6,
                static_cast<double>(r.max_latency_ns) / 1e6, r.shutter_marked, r.imminent_frames);
    return r.failures.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_gpio_camera: FAIL %s\n", e.what());
    return 1;
  }
}
