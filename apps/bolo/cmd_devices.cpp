// bolo devices: what the HAL finds on this machine: V4L2 nodes offering Y16 (or GREY/YUYV/UYVY) with their
// controls (a PureThermal's FPA / housing temperature through its Lepton extension unit), USB devices with a
// known VID:PID, gpiochips, and which backends this build has.

#include <iomanip>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bolo/errors.hpp"
#include "bolo/hal/device_spec.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/hal/gpio_lines.hpp"
#include "bolo/hal/uvc_controls.hpp"
#include "bolo/hal/v4l2_source.hpp"
#if defined(BOLO_HAVE_LIBUSB)
#include "bolo/hal/usb_libusb.hpp"
#endif
#include "bolo/registry.hpp"

namespace bolo::cli {
namespace {

#if defined(BOLO_HAVE_LIBUSB)
std::string hex4(unsigned v) {
  std::ostringstream o;
  o << std::hex << std::setw(4) << std::setfill('0') << v;
  return o.str();
}
#endif

// A V4L2 node's controls and, on a PureThermal, the Lepton's temperatures (degrees C; null unread).
nlohmann::json camera_controls(const std::string& node) {
  nlohmann::json j = {{"controls", nlohmann::json::array()}, {"purethermal", false}, {"fpa_temp_c", nullptr},
                      {"housing_temp_c", nullptr}, {"control_errors", nlohmann::json::array()}};
  try {
    hal::V4l2NodeControls controls(node);
    std::optional<hal::PureThermalControls> lepton;
    if (hal::is_purethermal_node(node)) lepton.emplace(node, controls);
    const hal::V4l2CameraReadout r = hal::read_v4l2_camera(controls, lepton ? &*lepton : nullptr);
    for (const hal::V4l2Control& c : r.controls)
      j["controls"].push_back({{"name", c.name}, {"id", c.id}, {"value", c.value ? nlohmann::json(*c.value) : nullptr},
                               {"min", c.minimum}, {"max", c.maximum}, {"step", c.step}, {"default", c.default_value},
                               {"read_only", c.read_only}});
    j["purethermal"] = r.purethermal;
    if (r.fpa_temp_mc) j["fpa_temp_c"] = *r.fpa_temp_mc / 1000.0;
    if (r.housing_temp_mc) j["housing_temp_c"] = *r.housing_temp_mc / 1000.0;
    for (const std::string& e : r.errors) j["control_errors"].push_back(e);
  } catch (const std::exception& e) {
    j["control_errors"].push_back(e.what());
  }
  return j;
}

std::string celsius(const nlohmann::json& value) {
  if (value.is_null()) return "unread";
  std::ostringstream o;
  o << std::fixed << std::setprecision(2) << value.get<double>() << " C";
  return o.str();
}

int run_devices(bool json, std::ostream& out) {
  const auto v4l2 = hal::list_v4l2_devices();
  nlohmann::json j = {{"v4l2", nlohmann::json::array()}, {"usb", nlohmann::json::array()},
                      {"gpio", nlohmann::json::array()},
                      {"backends", {{"v4l2", true}, {"usb", hal::usb_backend_available()},
                                    {"gpio", hal::gpio_backend_available()}}}};
  const auto size_list = [](const hal::V4l2Sizes& sizes) {
    nlohmann::json list = nlohmann::json::array();
    for (auto [w, h] : sizes) list.push_back(std::to_string(w) + "x" + std::to_string(h));
    return list;
  };
  for (const auto& d : v4l2) {
    // "formats" keeps the order the source tries them in (an array: JSON objects are sorted).
    nlohmann::json formats = nlohmann::json::array();
    for (const auto& f : d.formats)
      formats.push_back({{"format", hal::v4l2_pixels_name(f.pixels)}, {"sizes", size_list(f.sizes)},
                         {"tone_mapped", hal::tone_mapped(f.pixels)}});
    nlohmann::json entry = {{"device", "v4l2:" + d.path}, {"card", d.card}, {"driver", d.driver},
                            {"y16", size_list(d.sizes(hal::V4l2Pixels::y16))}, {"formats", formats}};
    entry.update(camera_controls(d.path));
    j["v4l2"].push_back(std::move(entry));
  }
#if defined(BOLO_HAVE_LIBUSB)
  for (const auto& d : hal::list_known_usb_devices())
    j["usb"].push_back({{"id", hex4(d.vendor_id) + ":" + hex4(d.product_id)}, {"bus", d.bus},
                       {"address", d.address}, {"what", d.what}});
#endif
  for (const auto& c : hal::list_gpiochips())
    j["gpio"].push_back({{"chip", c.name}, {"label", c.label}, {"lines", c.lines}});
  j["sources"] = nlohmann::json::array();
  for (const hal::SourceBackend& b : hal::source_schemes())
    j["sources"].push_back({{"spec", b.example()}, {"summary", b.summary}, {"available", b.unavailable.empty()}});
  if (json) {
    out << j.dump(2) << "\n";
    return kExitOk;
  }
  out << "V4L2 (Y16 counts; GREY, YUYV, UYVY: 8-bit tone-mapped):\n";
  if (j["v4l2"].empty()) out << "  none found\n";
  for (const auto& d : j["v4l2"]) {
    out << "  " << d["device"].get<std::string>() << "  " << d["card"].get<std::string>() << " ("
        << d["driver"].get<std::string>() << ")";
    const char* separator = " ";
    for (const auto& f : d["formats"]) {
      out << separator << " " << f["format"].get<std::string>();
      for (const auto& s : f["sizes"]) out << " " << s.get<std::string>();
      separator = ";";
    }
    out << "\n";
    if (d["purethermal"].get<bool>())
      out << "    PureThermal (Lepton commands): FPA " << celsius(d["fpa_temp_c"]) << ", housing "
          << celsius(d["housing_temp_c"]) << "; --shutter-at runs FFC\n";
    for (const auto& c : d["controls"]) {
      out << "    " << c["name"].get<std::string>() << " = "
          << (c["value"].is_null() ? std::string("?") : std::to_string(c["value"].get<int>())) << " ("
          << c["min"].get<int>() << ".." << c["max"].get<int>() << ", default " << c["default"].get<int>()
          << (c["read_only"].get<bool>() ? ", read-only" : "") << ")\n";
    }
    for (const auto& e : d["control_errors"]) out << "    " << e.get<std::string>() << "\n";
  }
  out << "USB:\n";
  if (!hal::usb_backend_available())
    out << "  backend compiled out (libusb-1.0 not found when this build was configured)\n";
  else if (j["usb"].empty())
    out << "  no known camera (FLIR ONE Pro 09cb:1996, Seek 289d:0010/0011, PureThermal 1e4e:0100)\n";
  for (const auto& d : j["usb"])
    out << "  " << d["id"].get<std::string>() << "  bus " << d["bus"].get<int>() << " address "
        << d["address"].get<int>() << "  " << d["what"].get<std::string>() << "\n";
  out << "GPIO:\n";
  if (!hal::gpio_backend_available())
    out << "  backend compiled out (libgpiod not found when this build was configured)\n";
  else if (j["gpio"].empty())
    out << "  no gpiochip\n";
  for (const auto& c : j["gpio"])
    out << "  " << c["chip"].get<std::string>() << "  " << c["label"].get<std::string>() << "  "
        << c["lines"].get<unsigned>() << " lines\n";
  out << "Source specs (bolo capture --device, bolo correct):\n";
  for (const hal::SourceBackend& b : hal::source_schemes())
    out << "  " << std::left << std::setw(18) << b.example() << " " << b.summary
        << (b.unavailable.empty() ? "" : " [compiled out]") << "\n";
  return kExitOk;
}

}  // namespace

Command add_devices_command(CLI::App& parent) {
  auto json = std::make_shared<bool>(false);
  CLI::App* app = add_command(
      parent, "devices", "List cameras and GPIO chips the HAL can use",
      "Lists V4L2 capture nodes that offer Y16 (the core's counts) or the 8-bit tone-mapped GREY,\n"
      "YUYV, UYVY (with their sizes and controls; a PureThermal's FPA and housing temperature read\n"
      "through its Lepton extension unit), USB devices with a known VID:PID (FLIR ONE Pro, Seek Thermal,\n"
      "PureThermal, Boson control), and gpiochips, each with the --device string `bolo capture` takes. A backend this build was configured\n"
      "without (no libusb-1.0 / libgpiod) is reported as compiled out.");
  app->add_flag("--json", *json, "Print JSON instead of text");
  return {app, [=](std::ostream& out) { return run_devices(*json, out); }};
}

}  // namespace bolo::cli
