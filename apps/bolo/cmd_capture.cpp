// bolo capture --device SPEC --out REC [--frames N]: records from any source hal::open_source
// opens (V4L2, USB cores, a recording, a captured FLIR ONE transfer log) into the shared
// recording format through the atomic RecordingWriter. Device faults are counted and reported;
// too many of them in a row give up with nothing written.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <optional>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/core/frame_collector.hpp"
#include "bolo/errors.hpp"
#include "bolo/hal/device_spec.hpp"
#include "bolo/hal/frame_reader.hpp"
#include "bolo/hal/gpio_synced_source.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/progress.hpp"
#include "bolo/recording/frame_row_header.hpp"
#include "bolo/recording/recording.hpp"
#include "bolo/registry.hpp"

namespace bolo::cli {
namespace {

namespace fs = std::filesystem;

struct CaptureOptions {
  std::string device;
  fs::path output;
  std::uint64_t frames = 0;  // 0 = until the source ends (file:, flirone-log: only)
  std::uint64_t max_faults = 50;
  std::string gpio;
  std::vector<std::uint64_t> shutter_at;  // frames before which a shutter event is requested
  bool overwrite = false;
  bool progress = true;
};

// --device takes a scheme always: a bare word is more likely a mistyped device than a folder.
constexpr hal::SourceOptions kDeviceOptions{.bare_path_is_recording = false};

// The backend a --device spec names, before anything is opened.
hal::SourceSpec parse_device(const std::string& text) {
  try {
    return hal::parse_source_spec(text, kDeviceOptions);
  } catch (const hal::SourceError& e) {
    fail("--device ", e.what());
  }
}

std::unique_ptr<hal::OpenedSource> open_named_source(const std::string& text) {
  try {
    return hal::open_source(text, kDeviceOptions);
  } catch (const hal::SourceError& e) {
    fail("--device ", e.what());
  }
}

int run_capture(const CaptureOptions& o, std::ostream& out) {
  if (o.output.empty()) fail("--out: required");
  if (!o.overwrite && fs::exists(o.output)) fail(o.output.string(), ": exists (use --overwrite to replace it)");
  std::optional<hal::GpioConfig> gpio_config;
  if (!o.gpio.empty()) {
    try {
      gpio_config = hal::parse_gpio_spec(o.gpio);
    } catch (const std::invalid_argument& e) {
      fail("--gpio ", o.gpio, ": ", e.what());
    }
    if (!hal::gpio_backend_available())
      fail("--gpio ", o.gpio, ": this build has no GPIO backend (libgpiod was not found when it was configured)");
  }
  const hal::SourceSpec spec = parse_device(o.device);
  const bool gpio_shutter = gpio_config && gpio_config->shutter_line >= 0;
  if (!spec.backend.finite && o.frames == 0) fail("--frames: required for a live camera (", o.device, ")");
  const std::unique_ptr<hal::OpenedSource> device = open_named_source(o.device);
  // Whether a V4L2 camera has one (a PureThermal) is known only once it is open.
  if (!o.shutter_at.empty() && !gpio_shutter && !device->has_shutter())
    fail("--shutter-at: ", o.device,
         " has no shutter control here (use --gpio CHIP:shutter=N, usb:seek, or a PureThermal on v4l2:)");

  hal::FrameSource* source = device.get();
  std::unique_ptr<hal::GpioLines> lines;
  std::unique_ptr<hal::GpioSyncedSource> synced;
#if defined(BOLO_HAVE_LIBGPIOD)
  if (gpio_config) {
    try {
      lines = std::make_unique<hal::GpiodLines>(*gpio_config);
    } catch (const std::exception& e) {
      fail("--gpio ", o.gpio, ": ", e.what());
    }
    synced = std::make_unique<hal::GpioSyncedSource>(*source, *lines);
    source = synced.get();
  }
#endif

  const hal::SourceFormat format = source->format();
  rec::RecordingInfo info = hal::recording_info_of(*device);
  info.source = "bolo capture --device " + o.device;
  info.notes = "t_s from the device's clock, relative to the first frame";

  std::vector<fw::Pixel> grab_storage(fw::FrameCollector::storage_pixels(format.width, format.height));
  fw::FrameCollector grab(format.width, format.height, grab_storage);
  rec::RecordingWriter writer(o.output, info, {o.overwrite});
  Progress progress("capture", o.frames, o.progress && o.frames != 0);
  rec::RowClock clock;
  hal::FrameReader reader(*source, o.max_faults);
  std::uint64_t captured = 0;
  bool ended = false;
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t shutters = 0;
  std::size_t next_shutter = 0;
  std::vector<std::uint64_t> shutter_at = o.shutter_at;
  std::sort(shutter_at.begin(), shutter_at.end());
  while (o.frames == 0 || captured < o.frames) {
    if (next_shutter < shutter_at.size() && shutter_at[next_shutter] <= captured) {
      ++next_shutter;
      const bool ok = synced && gpio_shutter ? synced->request_shutter() : device->request_shutter();
      shutters += ok ? 1 : 0;
    }
    const hal::FrameReader::Result r = reader.next(grab);
    if (r == hal::FrameReader::Result::ended) {
      ended = true;
      break;
    }
    // The source's own counters say what the stream did before it failed (e.g. frames the camera
    // skipped), next to the faults.
    if (r == hal::FrameReader::Result::gave_up)
      fail(o.device, ": gave up after ", o.max_faults, " faults in a row, ", captured,
           " frames captured, nothing written (", hal::fault_text(*source), ")");
    writer.append(grab.pixels(), clock.row(grab.header(), captured));
    progress.update(++captured);
  }
  progress.finish();
  if (captured == 0) fail(o.device, ": delivered no frames, nothing written");
  const hal::SourceStats stats = source->stats();
  const hal::ExtraCounters counters = source->extra_counters();
  nlohmann::json extra = hal::source_record(o.device, *source, clock.not_increasing());
  if (synced && synced->latency().count > 0)
    extra["sync_latency_ns"] = {{"count", synced->latency().count}, {"min", synced->latency().min_ns},
                                {"mean", synced->latency().mean_ns()}, {"max", synced->latency().max_ns}};
  writer.add_file("capture.json", extra.dump(2) + "\n");
  writer.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  out << "captured " << captured << " frames (" << format.width << "x" << format.height << ") from " << o.device
      << " into " << o.output.string() << " in " << std::fixed << std::setprecision(1) << seconds << " s\n";
  if (ended && o.frames != 0 && captured < o.frames)
    out << "the source ended after " << captured << " of " << o.frames << " frames\n";
  out << "device faults: " << hal::stats_text(stats) << "\n";
  if (!counters.items().empty()) out << "device counters: " << hal::extra_counters_text(counters) << "\n";
  if (!shutter_at.empty()) out << "shutter events requested: " << shutters << " of " << shutter_at.size() << "\n";
  if (clock.not_increasing() > 0)
    out << clock.not_increasing() << " frames with a time stamp not after the previous one: t_s left empty\n";
  if (synced && synced->latency().count > 0)
    out << "sync-to-frame latency: mean " << synced->latency().mean_ns() / 1000 << " us over "
        << synced->latency().count << " frames\n";
  return kExitOk;
}

// The registered source specs, one per line, for the help page.
std::string source_list() {
  std::ostringstream text;
  for (const hal::SourceBackend& b : hal::source_schemes())
    text << "  " << std::left << std::setw(18) << b.example() << " " << b.summary << "\n";
  return text.str();
}

}  // namespace

Command add_capture_command(CLI::App& parent) {
  auto o = std::make_shared<CaptureOptions>();
  CLI::App* app = add_command(
      parent, "capture", "Record frames from a camera (V4L2, USB) or a recording into a recording",
      "Records from any frame source of the HAL into a recording in the shared format\n"
      "(frames.npy, frames.csv with time, FFC and temperatures where the device reports them,\n"
      "recording.json, capture.json with the device's fault and extra counters). Devices:\n" +
          source_list() +
          "Faults (timeouts, short or corrupt transfers, unplugs) are counted and skipped; more than\n"
      "--max-faults in a row give up and write nothing. `bolo devices` lists what is connected.\n\n"
      "Example:\n"
      "  bolo capture --device v4l2:/dev/video0 --out lepton-run --frames 500");
  app->add_option("--device", o->device, "Where frames come from (see above)")->required();
  app->add_option("--out", o->output, "Output recording folder (must not exist unless --overwrite)")->required();
  app->add_option("--frames", o->frames, "Frames to record (default for file:/flirone-log: all)")
      ->check(not_negative());
  app->add_option("--max-faults", o->max_faults, "Faults in a row before giving up (default 50)")
      ->check(not_negative());
  app->add_option("--gpio", o->gpio,
                  "GPIO lines beside the camera, CHIP:sync=N,shutter=N,imminent=N (sync-to-frame latency)");
  app->add_option("--shutter-at", o->shutter_at,
                  "Request a shutter (FFC) event before frame N (repeatable; through --gpio's shutter line,\n"
                  "usb:seek's own command, or a PureThermal's Lepton Run FFC); the frame after it is marked\n"
                  "ffc in frames.csv (PureThermal: from its telemetry rows, where the format has them)")
      ->check(not_negative());
  app->add_flag("--overwrite", o->overwrite, "Replace OUT if it exists");
  app->add_flag("--no-progress", [o](std::int64_t) { o->progress = false; },
                "Never draw the progress bar (it is drawn only when stderr is a terminal)");
  return {app, [=](std::ostream& out) { return run_capture(*o, out); }};
}

}  // namespace bolo::cli
