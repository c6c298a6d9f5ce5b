// The PureThermal Lepton command table and its request / reply bytes, each expected value worked
// out here from the Lepton IDD command id and the firmware's unit / selector rule, not from the code.

#include <catch2/catch.hpp>

#include <array>
#include <string>
#include <vector>

#include "bolo/hal/purethermal_xu.hpp"
#include "fake_uvc_xu.hpp"

using namespace bolo::hal;

TEST_CASE("each Lepton command has the PureThermal unit, selector and length", "[hal][purethermal]") {
  struct Expected {
    const LeptonXuCommand& command;
    int unit, selector, length;
  };
  // SYS is unit 6, RAD 5, AGC 3; selector = offset / 4 + 1: Run FFC 0x42 -> 16 + 1, FPA 0x14 -> 5 + 1,
  // AUX 0x10 -> 4 + 1, gain mode 0x48 -> 18 + 1, RAD enable 0x10 -> 4 + 1, AGC enable 0x00 -> 0 + 1.
  const std::array<Expected, 6> table{{{kLeptonRunFfc, 6, 17, 1},
                                       {kLeptonFpaTemperature, 6, 6, 2},
                                       {kLeptonHousingTemperature, 6, 5, 2},
                                       {kLeptonGainMode, 6, 19, 4},
                                       {kLeptonRadiometry, 5, 5, 4},
                                       {kLeptonAgc, 3, 1, 4}}};
  for (const Expected& e : table) {
    INFO(e.command.name);
    CHECK(purethermal_xu_unit(e.command.command_id) == e.unit);
    CHECK(purethermal_xu_selector(e.command.command_id) == e.selector);
    CHECK(purethermal_xu_length(e.command) == static_cast<std::size_t>(e.length));
  }
  CHECK(purethermal_xu_unit(0x0800) == 4);  // OEM
  CHECK(purethermal_xu_unit(0x0300) == 7);  // VID
  CHECK(purethermal_xu_unit(0x0500) == 0);  // no such module
}

TEST_CASE("a run command is one byte, a value its words low byte first", "[hal][purethermal]") {
  std::array<std::uint8_t, 4> out{0xAA, 0xAA, 0xAA, 0xAA};
  REQUIRE(encode_purethermal_set(kLeptonRunFfc, 0, out) == 1);
  CHECK(out[0] == 0x00);
  CHECK(out[1] == 0xAA);

  REQUIRE(encode_purethermal_set(kLeptonGainMode, 1, out) == 4);  // low gain
  CHECK(out == std::array<std::uint8_t, 4>{0x01, 0x00, 0x00, 0x00});
  REQUIRE(encode_purethermal_set(kLeptonAgc, 0x00020001, out) == 4);  // word 0 = 0x0001, word 1 = 0x0002
  CHECK(out == std::array<std::uint8_t, 4>{0x01, 0x00, 0x02, 0x00});

  CHECK(encode_purethermal_set(kLeptonFpaTemperature, 30000, out) == 0);  // read-only
  std::array<std::uint8_t, 3> small{};
  CHECK(encode_purethermal_set(kLeptonRadiometry, 1, small) == 0);  // too small for two words
}

TEST_CASE("replies decode: kelvin x 100 to milli-degrees Celsius, enumerations as they are", "[hal][purethermal]") {
  // 30015 cK = 0x753F = 300.15 K = 27.00 degC.
  const std::array<std::uint8_t, 2> fpa{0x3F, 0x75};
  CHECK(decode_purethermal_reply(kLeptonFpaTemperature, fpa) == 27000);
  // 29815 cK = 0x7477 = 298.15 K = 25.00 degC.
  const std::array<std::uint8_t, 2> housing{0x77, 0x74};
  CHECK(decode_purethermal_reply(kLeptonHousingTemperature, housing) == 25000);
  const std::array<std::uint8_t, 4> gain{0x02, 0x00, 0x00, 0x00};  // auto
  CHECK(decode_purethermal_reply(kLeptonGainMode, gain) == 2);

  const std::array<std::uint8_t, 2> zero{0, 0};
  CHECK_FALSE(decode_purethermal_reply(kLeptonFpaTemperature, zero));  // no reading
  CHECK_FALSE(decode_purethermal_reply(kLeptonFpaTemperature, gain));  // wrong length
  CHECK_FALSE(decode_purethermal_reply(kLeptonRunFfc, std::array<std::uint8_t, 1>{0}));
}


TEST_CASE("a PureThermal is the device with the Lepton SYS extension unit", "[hal][purethermal]") {
  CHECK(has_purethermal_sys_unit(bolo::test::descriptors_with_extension_unit(6, "pt1-lep-sys-0000")));
  CHECK_FALSE(has_purethermal_sys_unit(bolo::test::descriptors_with_extension_unit(5, "pt1-lep-sys-0000")));  // another unit id
  CHECK_FALSE(has_purethermal_sys_unit(bolo::test::descriptors_with_extension_unit(6, "pt1-lep-rad-0000")));  // another module
  std::vector<std::uint8_t> cut = bolo::test::descriptors_with_extension_unit(6, "pt1-lep-sys-0000");
  cut.resize(cut.size() - 10);  // the unit's descriptor runs past the end
  CHECK_FALSE(has_purethermal_sys_unit(cut));
  CHECK_FALSE(has_purethermal_sys_unit({}));
  const auto guid = purethermal_xu_guid(3);
  REQUIRE(guid);
  CHECK(std::string(guid->begin(), guid->end()) == "pt1-lep-agc-0000");
  CHECK_FALSE(purethermal_xu_guid(9));
}
