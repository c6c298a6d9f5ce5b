// The emulated PureThermal's Lepton command interface without a VM: what it answers on its
// extension units, what it stores, the Run FFC it hands to the stream, what it refuses and counts.

#include <catch2/catch.hpp>

#include "bolo/hal/purethermal_xu.hpp"
#include "emulators/uvc_control.hpp"
#include "emulators/uvc_lepton.hpp"

using namespace bolo;
using hil::uvc::LeptonXu;
using XuBytes = std::vector<std::uint8_t>;

namespace {

constexpr std::uint8_t kSys = 6, kRad = 5, kAgc = 3;
std::uint8_t selector_of(const hal::LeptonXuCommand& c) { return hal::purethermal_xu_selector(c.command_id); }

}  // namespace

TEST_CASE("uvc_lepton: the controls' length, capabilities and readings as uvcvideo asks for them", "[hil][uvc]") {
  LeptonXu xu(30000, 30150);
  CHECK(xu.get(hil::uvc::kGetLen, kSys, selector_of(hal::kLeptonRunFfc), 2) == XuBytes{1, 0});
  CHECK(xu.get(hil::uvc::kGetInfo, kSys, selector_of(hal::kLeptonRunFfc), 1) == XuBytes{0x02});  // SET only
  CHECK(xu.get(hil::uvc::kGetLen, kSys, selector_of(hal::kLeptonFpaTemperature), 2) == XuBytes{2, 0});
  CHECK(xu.get(hil::uvc::kGetInfo, kSys, selector_of(hal::kLeptonFpaTemperature), 1) == XuBytes{0x01});  // GET only
  CHECK(xu.get(hil::uvc::kGetLen, kSys, selector_of(hal::kLeptonGainMode), 2) == XuBytes{4, 0});
  CHECK(xu.get(hil::uvc::kGetInfo, kSys, selector_of(hal::kLeptonGainMode), 1) == XuBytes{0x03});
  // 30000 cK, 30150 cK little endian; read back by the HAL's own decoder as 26.85 / 28.35 degC.
  const auto fpa = xu.get(hil::uvc::kGetCur, kSys, selector_of(hal::kLeptonFpaTemperature), 2);
  REQUIRE(fpa);
  CHECK(hal::decode_purethermal_reply(hal::kLeptonFpaTemperature, *fpa) == 26850);
  const auto aux = xu.get(hil::uvc::kGetCur, kSys, selector_of(hal::kLeptonHousingTemperature), 2);
  REQUIRE(aux);
  CHECK(hal::decode_purethermal_reply(hal::kLeptonHousingTemperature, *aux) == 28350);
  CHECK(xu.get(hil::uvc::kGetMax, kSys, selector_of(hal::kLeptonGainMode), 4) == XuBytes{2, 0, 0, 0});
  CHECK(xu.get(hil::uvc::kGetDef, kRad, selector_of(hal::kLeptonRadiometry), 4) == XuBytes{1, 0, 0, 0});
  CHECK(xu.answered() == 10);
  CHECK(xu.refused() == 0);
}

TEST_CASE("uvc_lepton: settings stored and read back, Run FFC handed to the stream once", "[hil][uvc]") {
  LeptonXu xu(30000, 30150);
  CHECK(xu.get(hil::uvc::kGetCur, kSys, selector_of(hal::kLeptonGainMode), 4) == XuBytes{0, 0, 0, 0});  // high
  REQUIRE(xu.accepts_set(hil::uvc::kSetCur, kSys, selector_of(hal::kLeptonGainMode), 4));
  xu.set(kSys, selector_of(hal::kLeptonGainMode), XuBytes{1, 0, 0, 0});
  CHECK(xu.get(hil::uvc::kGetCur, kSys, selector_of(hal::kLeptonGainMode), 4) == XuBytes{1, 0, 0, 0});
  CHECK(xu.last() == "GET_CUR SYS gain mode (unit 6, selector 19): 1");
  REQUIRE(xu.accepts_set(hil::uvc::kSetCur, kAgc, selector_of(hal::kLeptonAgc), 4));
  xu.set(kAgc, selector_of(hal::kLeptonAgc), XuBytes{1, 0, 0, 0});
  CHECK(xu.get(hil::uvc::kGetCur, kAgc, selector_of(hal::kLeptonAgc), 4) == XuBytes{1, 0, 0, 0});

  CHECK_FALSE(xu.take_ffc());
  REQUIRE(xu.accepts_set(hil::uvc::kSetCur, kSys, selector_of(hal::kLeptonRunFfc), 1));
  xu.set(kSys, selector_of(hal::kLeptonRunFfc), XuBytes{0});
  CHECK(xu.ffc_runs() == 1);
  CHECK(xu.take_ffc());
  CHECK_FALSE(xu.take_ffc());
  CHECK(xu.refused() == 0);

  // A gain mode out of range is ignored and counted; the request error code says so.
  REQUIRE(xu.accepts_set(hil::uvc::kSetCur, kSys, selector_of(hal::kLeptonGainMode), 4));
  xu.set(kSys, selector_of(hal::kLeptonGainMode), XuBytes{3, 0, 0, 0});
  CHECK(xu.refused() == 1);
  CHECK(xu.get(hil::uvc::kGetCur, 0, 2, 1) == XuBytes{4});  // out of range
  CHECK(xu.get(hil::uvc::kGetCur, kSys, selector_of(hal::kLeptonGainMode), 4) == XuBytes{1, 0, 0, 0});
}

TEST_CASE("uvc_lepton: unknown units and selectors, reads of a run command, writes of a reading are stalled and counted",
          "[hil][uvc]") {
  LeptonXu xu(30000, 30150);
  CHECK_FALSE(xu.get(hil::uvc::kGetCur, kSys, 2, 4));  // SYS selector 2: no command bolo uses
  CHECK(xu.get(hil::uvc::kGetCur, 0, 2, 1) == XuBytes{6});  // invalid control
  CHECK_FALSE(xu.get(hil::uvc::kGetInfo, 9, 1, 1));  // no unit 9
  CHECK(xu.get(hil::uvc::kGetCur, 0, 2, 1) == XuBytes{5});  // invalid unit
  CHECK_FALSE(xu.get(hil::uvc::kGetCur, kSys, selector_of(hal::kLeptonRunFfc), 1));
  CHECK_FALSE(xu.accepts_set(hil::uvc::kSetCur, kSys, selector_of(hal::kLeptonFpaTemperature), 2));
  CHECK_FALSE(xu.accepts_set(hil::uvc::kSetCur, kSys, selector_of(hal::kLeptonGainMode), 2));  // wrong length
  CHECK(xu.get(hil::uvc::kGetCur, 0, 2, 1) == XuBytes{7});  // invalid request
  CHECK(xu.refused() == 5);
  // uvcvideo's standard controls of the processing unit are none of the Lepton's: counted apart.
  CHECK_FALSE(xu.get(hil::uvc::kGetInfo, 2, 2, 1));
  CHECK(xu.refused() == 5);
  CHECK(xu.refused_other() == 1);
  CHECK(xu.answered() == 0);
}

TEST_CASE("uvc_lepton: a board told to refuse stalls every extension-unit request", "[hil][uvc]") {
  LeptonXu xu(30000, 30150, true);
  CHECK_FALSE(xu.get(hil::uvc::kGetLen, kSys, selector_of(hal::kLeptonRunFfc), 2));
  CHECK_FALSE(xu.accepts_set(hil::uvc::kSetCur, kSys, selector_of(hal::kLeptonRunFfc), 1));
  CHECK(xu.refused() == 2);
  CHECK(xu.answered() == 0);
}
