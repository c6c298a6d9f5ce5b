// The FLIR ONE start and stop sequence, through the UsbDeviceSetup seam, against a scripted
// device that knows the public drivers' order (usb-thermal-cores.md, written out here apart from
// the HAL's table) and refuses any other request.

#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "bolo/hal/usb_setup.hpp"
#if defined(BOLO_HAVE_LIBUSB)
#include "bolo/hal/usb_libusb.hpp"
#endif

using namespace bolo;

namespace {

// Accepts exactly its script, in order; the first request off it is refused and every later one too.
class ScriptedDevice final : public hal::UsbDeviceSetup {
 public:
  explicit ScriptedDevice(std::vector<std::string> script) : script_(std::move(script)) {}
  bool set_configuration(std::uint8_t c) override { return take("config " + std::to_string(c)); }
  bool claim_interface(std::uint8_t i) override { return take("claim " + std::to_string(i)); }
  bool set_interface(std::uint8_t i, std::uint8_t alt) override {
    return take("interface " + std::to_string(i) + " alt " + std::to_string(alt));
  }
  bool finished() const { return !refused_ && at_ == script_.size(); }
  std::vector<std::string> refused;

 private:
  bool take(const std::string& request) {
    if (!refused_ && at_ < script_.size() && script_[at_] == request) {
      ++at_;
      return true;
    }
    refused_ = true;
    refused.push_back(request);
    return false;
  }
  std::vector<std::string> script_;
  std::size_t at_ = 0;
  bool refused_ = false;
};

const std::vector<std::string> kDriversStart = {
    "config 3",           "claim 0",            "claim 1",           "claim 2",
    "interface 2 alt 0",  "interface 1 alt 0",  "interface 1 alt 1", "interface 2 alt 1"};
const std::vector<std::string> kDriversStop = {"interface 2 alt 0", "interface 1 alt 0"};

}  // namespace

TEST_CASE("FLIR ONE start-up is the public drivers' sequence, step by step", "[hal][flirone]") {
  ScriptedDevice device(kDriversStart);
  CHECK(hal::run_usb_setup(device, hal::flirone::kStartSteps) == std::size(hal::flirone::kStartSteps));
  CHECK(device.finished());
  CHECK(device.refused.empty());

  ScriptedDevice stopping(kDriversStop);
  CHECK(hal::run_usb_setup(stopping, hal::flirone::kStopSteps) == std::size(hal::flirone::kStopSteps));
  CHECK(stopping.finished());
}

TEST_CASE("a start-up out of the drivers' order stops at the refused step", "[hal][flirone]") {
  ScriptedDevice device(kDriversStart);
  const hal::UsbSetupStep frames_first[] = {
      {hal::UsbSetupKind::set_configuration, 3}, {hal::UsbSetupKind::claim_interface, 0},
      {hal::UsbSetupKind::claim_interface, 1},   {hal::UsbSetupKind::claim_interface, 2},
      {hal::UsbSetupKind::set_interface, 2, 1},  {hal::UsbSetupKind::set_interface, 1, 1}};
  CHECK(hal::run_usb_setup(device, frames_first) == 4);
  CHECK(device.refused == std::vector<std::string>{"interface 2 alt 1"});
  CHECK_FALSE(device.finished());

  char text[48];
  hal::describe_usb_step(frames_first[4], text, sizeof text);
  CHECK(std::string(text) == "SET_INTERFACE 2 alt 1");
}

#if defined(BOLO_HAVE_LIBUSB)
TEST_CASE("usb:flirone's libusb transport runs the drivers' start and stop sequence", "[hal][flirone]") {
  const hal::LibusbConfig config = hal::flirone_libusb_config();
  ScriptedDevice device(kDriversStart);
  CHECK(hal::run_usb_setup(device, config.start) == config.start.size());
  CHECK(device.finished());
  ScriptedDevice stopping(kDriversStop);
  CHECK(hal::run_usb_setup(stopping, config.stop) == config.stop.size());
  CHECK(stopping.finished());
}
#endif
