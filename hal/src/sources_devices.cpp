// v4l2:, usb:flirone, usb:seek (cameras) and flirone-log: (a captured FLIR ONE transfer log
// replayed through the same source as usb:flirone).

#include <stdexcept>

#include "bolo/hal/captured_transfers.hpp"
#include "bolo/hal/device_spec.hpp"
#include "bolo/hal/flirone_source.hpp"
#include "bolo/hal/seek_source.hpp"
#include "bolo/hal/uvc_controls.hpp"
#include "bolo/hal/v4l2_source.hpp"
#if defined(BOLO_HAVE_LIBUSB)
#include "bolo/hal/usb_libusb.hpp"
#endif
#include "builtin_sources.hpp"

namespace bolo::hal::detail {
namespace {

// A FlirOneSource that has read the camera's first frame, so that its format (80x60 or 160x120)
// is the core's before anyone records; the frame is delivered first.
std::unique_ptr<OpenedSource> open_flirone(BulkInTransport& transport, std::shared_ptr<void> keep,
                                           const std::string& what) {
  auto source = std::make_unique<FlirOneSource>(transport);
  source->probe();
  const SourceFormat f = source->format();
  std::string sensor = "FLIR ONE (" + std::to_string(f.width) + "x" + std::to_string(f.height) + " core)" + what;
  return std::make_unique<OpenedSource>(std::move(source), std::move(sensor), std::move(keep));
}

// Set on the usb: backends of a build configured without libusb-1.0.
constexpr const char* kNoUsb =
    "this build has no USB backend (libusb-1.0 was not found when it was configured; see `bolo devices`)";

struct V4l2Spec {
  V4l2Config config;
  LeptonSettings lepton;  // for a PureThermal's extension units
};

// "/dev/video0?format=GREY,gain=low": the node and the options after '?' (format=Y16|GREY|YUYV|UYVY,
// the Lepton settings of device_spec.hpp).
V4l2Spec v4l2_spec_of(const std::string& argument) {
  const std::size_t question = argument.find('?');
  V4l2Spec spec;
  spec.config.path = argument.substr(0, question);
  if (question == std::string::npos) return spec;
  for (const SpecOption& option : parse_spec_options(argument.substr(question + 1))) {
    if (parse_lepton_option(option, spec.lepton)) continue;
    if (option.key != "format")
      throw std::invalid_argument(unexpected_option(option, std::string("format=Y16|GREY|YUYV|UYVY or ") + kLeptonOptions));
    spec.config.pixels = v4l2_pixels_named(option.value);
    if (!spec.config.pixels) throw std::invalid_argument("format=" + option.value + ": expected Y16, GREY, YUYV or UYVY");
  }
  return spec;
}

// The spec's Lepton settings sent to the PureThermal (`xu` null: the camera is none). Throws naming
// the node and, for a refusal, the command.
void apply_lepton_settings(const std::string& node, const LeptonSettings& settings, UvcExtensionUnit* xu) {
  if (xu == nullptr)
    throw std::runtime_error(node + ": " + kLeptonOptions + " need a PureThermal (Lepton extension units); this camera has none");
  PureThermalControls lepton(node, *xu);
  if (!lepton.apply(settings)) throw std::runtime_error(lepton.last_error());
}

SourceBackend v4l2_backend() {
  SourceBackend b;
  b.scheme = "v4l2";
  b.argument = "/dev/videoN";
  b.argument_help = "a device node, e.g. v4l2:/dev/video0";
  b.summary = "UVC camera: Y16 (Lepton on PureThermal: 160x122 / 80x63 with telemetry, FFC as shutter, "
              "?gain=high|low|auto,radiometry=on|off,agc=on|off), else 8-bit GREY/YUYV/UYVY";
  b.check = [](const std::string& argument) { (void)v4l2_spec_of(argument); };
  b.open = [](const std::string& argument, const SourceOptions&) {
    const V4l2Spec spec = v4l2_spec_of(argument);
    const V4l2Config& config = spec.config;
    auto v4l2 = std::make_unique<V4l2Source>(config);
    const V4l2Negotiated& n = v4l2->negotiated();
    std::string sensor = n.card + " (V4L2 " + v4l2_pixels_name(n.pixels) +
                         (tone_mapped(n.pixels) ? ", 8-bit tone-mapped, " : ", ") + n.driver + ")";
    // A PureThermal's shutter: Lepton SYS Run FFC through its extension unit.
    const bool purethermal = is_purethermal_node(config.path);
    std::shared_ptr<V4l2NodeControls> controls;
    if (purethermal) controls = std::make_shared<V4l2NodeControls>(config.path);
    auto shutter = v4l2_shutter_command(config.path, purethermal, controls);
    if (!spec.lepton.empty()) apply_lepton_settings(config.path, spec.lepton, controls.get());
    return std::make_unique<OpenedSource>(std::move(v4l2), std::move(sensor), std::move(controls), std::move(shutter));
  };
  return b;
}

SourceBackend flirone_backend() {
  SourceBackend b;
  b.scheme = "usb:flirone";
  b.summary = "FLIR ONE Gen 3 / Pro (libusb)";
#if defined(BOLO_HAVE_LIBUSB)
  b.open = [](const std::string&, const SourceOptions&) {
    auto usb = std::make_shared<LibusbTransport>(flirone_libusb_config());
    LibusbTransport& transport = *usb;
    return open_flirone(transport, std::move(usb), "");
  };
#else
  b.unavailable = kNoUsb;
#endif
  return b;
}

SourceBackend seek_backend() {
  SourceBackend b;
  b.scheme = "usb:seek";
  b.summary = "Seek Thermal Compact / CompactPro (libusb)";
  b.shutter = true;
#if defined(BOLO_HAVE_LIBUSB)
  b.open = [](const std::string&, const SourceOptions&) {
    auto usb = std::make_shared<LibusbTransport>(seek_libusb_config());
    const SeekModel& model =
        usb->opened().product_id == kSeekCompactPro.product_id ? kSeekCompactPro : kSeekCompact;
    auto seek = std::make_unique<SeekSource>(*usb, model);
    SeekSource* shutter = seek.get();
    return std::make_unique<OpenedSource>(std::move(seek), std::string("Seek Thermal ") + model.name, usb,
                                          [shutter] { return shutter->request_shutter(); });
  };
#else
  b.unavailable = kNoUsb;
#endif
  return b;
}

}  // namespace

void add_device_sources(std::vector<SourceBackend>& backends) {
  backends.push_back(v4l2_backend());
  backends.push_back(flirone_backend());
  backends.push_back(seek_backend());
}

void add_replay_sources(std::vector<SourceBackend>& backends) {
  SourceBackend b;
  b.scheme = "flirone-log";
  b.argument = "DIR";
  b.argument_help = "a transfer-log folder";
  b.summary = "a captured FLIR ONE bulk-transfer log (N.txt hex files)";
  b.finite = true;
  b.open = [](const std::string& dir, const SourceOptions&) {
    auto log = std::make_shared<CapturedTransfers>(dir);
    CapturedTransfers& transport = *log;
    return open_flirone(transport, std::move(log), ", replayed transfer log");
  };
  backends.push_back(std::move(b));
}

}  // namespace bolo::hal::detail
