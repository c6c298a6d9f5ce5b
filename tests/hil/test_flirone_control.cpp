// The FLIR ONE emulator's start-up check (flirone_control.hpp, written from the protocol facts)
// takes the HAL's start and stop sequence as the wire carries it, and refuses wrong start-ups:
// the old vendor request, SET_INTERFACE out of the drivers' order, a wrong configuration.

#include <catch2/catch.hpp>

#include "bolo/hal/usb_setup.hpp"
#include "emulators/flirone_control.hpp"

using namespace bolo;
using hil::flirone::StartupChecker;

namespace {

usb_ctrlrequest request(std::uint8_t type, std::uint8_t code, std::uint16_t value, std::uint16_t index,
                        std::uint16_t length = 0) {
  usb_ctrlrequest r{};
  r.bRequestType = type;
  r.bRequest = code;
  r.wValue = value;
  r.wIndex = index;
  r.wLength = length;
  return r;
}

// The HAL's steps as the wire carries them (claims send nothing).
class Wire final : public hal::UsbDeviceSetup {
 public:
  explicit Wire(StartupChecker& c) : checker(c) {}
  bool set_configuration(std::uint8_t c) override { return checker.take(request(0x00, 0x09, c, 0)); }
  bool claim_interface(std::uint8_t) override { return true; }
  bool set_interface(std::uint8_t i, std::uint8_t alt) override { return checker.take(request(0x01, 0x0b, alt, i)); }
  StartupChecker& checker;
};

}  // namespace

TEST_CASE("the emulator streams after the HAL's start sequence and stops after its stop sequence", "[hil][flirone]") {
  StartupChecker checker;
  Wire wire(checker);
  CHECK(hal::run_usb_setup(wire, hal::flirone::kStartSteps) == std::size(hal::flirone::kStartSteps));
  CHECK(checker.streaming());
  CHECK(hal::run_usb_setup(wire, hal::flirone::kStopSteps) == std::size(hal::flirone::kStopSteps));
  CHECK_FALSE(checker.streaming());
  // A reopen without a replug: configuration 3 again, the whole sequence again.
  CHECK(hal::run_usb_setup(wire, hal::flirone::kStartSteps) == std::size(hal::flirone::kStartSteps));
  CHECK(checker.streaming());
  CHECK(checker.refused() == 0);
}

TEST_CASE("wrong start-ups are refused and counted, and no frames flow", "[hil][flirone]") {
  SECTION("the vendor request alone (bmRequestType 0x41, request 0x0b)") {
    StartupChecker checker;
    CHECK(checker.take(request(0x00, 0x09, 3, 0)));
    CHECK_FALSE(checker.take(request(0x41, 0x0b, 1, 2)));
    CHECK_FALSE(checker.streaming());
    CHECK(checker.refused() == 1);
  }
  SECTION("frames started before file I/O") {
    StartupChecker checker;
    CHECK(checker.take(request(0x00, 0x09, 3, 0)));
    CHECK(checker.take(request(0x01, 0x0b, 0, 2)));
    CHECK(checker.take(request(0x01, 0x0b, 0, 1)));
    CHECK_FALSE(checker.take(request(0x01, 0x0b, 1, 2)));
    CHECK_FALSE(checker.streaming());
    CHECK(checker.refused() == 1);
  }
  SECTION("SET_INTERFACE without SET_CONFIGURATION 3, or another configuration") {
    StartupChecker checker;
    CHECK_FALSE(checker.take(request(0x01, 0x0b, 0, 2)));
    CHECK_FALSE(checker.take(request(0x00, 0x09, 1, 0)));
    CHECK(checker.refused() == 2);
  }
  SECTION("the frames' start with two data bytes, as flirone-v4l2 sends it, is taken") {
    StartupChecker checker;
    for (const usb_ctrlrequest& r : {request(0x00, 0x09, 3, 0), request(0x01, 0x0b, 0, 2), request(0x01, 0x0b, 0, 1),
                                     request(0x01, 0x0b, 1, 1), request(0x01, 0x0b, 1, 2, 2)})
      CHECK(checker.take(r));
    CHECK(checker.streaming());
  }
}

TEST_CASE("the emulator's descriptors: 09cb:1996, configuration 3, three interfaces with alt 0 and 1", "[hil][flirone]") {
  const hil::flirone::EndpointPair eps[3] = {{0x81, 0x02}, {0x86, 0x07}, {0x8b, 0x06}};
  const hil::flirone::Descriptors d = hil::flirone::make_descriptors(eps);
  CHECK(d.device[8] == 0xcb);
  CHECK(d.device[9] == 0x09);
  CHECK(d.device[10] == 0x96);
  CHECK(d.device[11] == 0x19);
  CHECK(d.configuration[5] == 3);
  CHECK(d.configuration.size() == 9 + 6 * (9 + 2 * 7));
  CHECK((d.configuration[2] | (d.configuration[3] << 8)) == static_cast<int>(d.configuration.size()));
}
