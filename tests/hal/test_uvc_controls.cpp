// The V4L2 camera's controls behind their seams: the PureThermal's Lepton commands through a fake
// extension unit, the shutter command a V4L2 camera gets, PureThermal detection from sysfs.

#include <catch2/catch.hpp>

#include <fstream>

#include "../test_support.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/hal/uvc_controls.hpp"
#include "fake_uvc_xu.hpp"

using namespace bolo;
using bolo::test::FakeUvcXu;

namespace {

// A source that never delivers: the shutter is what is under test.
class IdleSource final : public hal::FrameSource {
 public:
  hal::SourceFormat format() const override { return {}; }
  hal::StreamStatus stream_frame(fw::LineSink&) override { return hal::StreamStatus::end_of_stream; }
  hal::SourceStats stats() const override { return {}; }
};

hal::OpenedSource camera(bool purethermal, std::shared_ptr<FakeUvcXu> xu) {
  return hal::OpenedSource(std::make_unique<IdleSource>(), "camera", {},
                           hal::v4l2_shutter_command("/dev/video7", purethermal, xu));
}

}  // namespace

TEST_CASE("a PureThermal's shutter is exactly Lepton SYS Run FFC: unit 6, selector 17, SET_CUR, one byte",
          "[hal][purethermal]") {
  auto xu = std::make_shared<FakeUvcXu>();
  hal::OpenedSource source = camera(true, xu);
  REQUIRE(source.has_shutter());
  CHECK(source.request_shutter());
  REQUIRE(xu->log.size() == 1);
  CHECK(xu->log[0].unit == 6);
  CHECK(xu->log[0].selector == 17);
  CHECK(xu->log[0].request == hal::UvcRequest::set_cur);
  CHECK(xu->log[0].data.size() == 1);
}

TEST_CASE("another V4L2 camera has no shutter command", "[hal][purethermal]") {
  auto xu = std::make_shared<FakeUvcXu>();
  hal::OpenedSource source = camera(false, xu);
  CHECK_FALSE(source.has_shutter());
  CHECK_FALSE(source.request_shutter());
  CHECK(xu->log.empty());
}

TEST_CASE("Lepton commands through the extension unit, a refusal naming the node and the control", "[hal][purethermal]") {
  FakeUvcXu xu;
  xu.replies[{6, 6}] = {0x3F, 0x75};  // FPA 30015 cK = 27.00 degC
  xu.replies[{6, 5}] = {0x77, 0x74};  // AUX 29815 cK = 25.00 degC
  hal::PureThermalControls lepton("/dev/video7", xu);
  CHECK(lepton.get(hal::kLeptonFpaTemperature) == 27000);
  CHECK(lepton.get(hal::kLeptonHousingTemperature) == 25000);
  REQUIRE(xu.log.size() == 2);
  CHECK((xu.log[0].unit == 6 && xu.log[0].selector == 6 && xu.log[0].request == hal::UvcRequest::get_cur));

  CHECK(lepton.set(hal::kLeptonAgc, 0));  // AGC off: unit 3, selector 1, two words of 0
  CHECK((xu.log.back().unit == 3 && xu.log.back().selector == 1));
  CHECK(xu.log.back().data == std::vector<std::uint8_t>{0, 0, 0, 0});
  CHECK(lepton.set(hal::kLeptonRadiometry, 1));
  CHECK((xu.log.back().unit == 5 && xu.log.back().selector == 5));
  CHECK(xu.log.back().data == std::vector<std::uint8_t>{1, 0, 0, 0});

  CHECK_FALSE(lepton.get(hal::kLeptonGainMode));  // no reply in the table: stalled
  CHECK(lepton.last_error() == "/dev/video7: Lepton SYS gain mode (XU unit 6, selector 19): GET_CUR: Broken pipe");
  xu.refuse = EIO;
  CHECK_FALSE(lepton.run_ffc());
  CHECK(lepton.last_error() == "/dev/video7: Lepton SYS Run FFC (XU unit 6, selector 17): SET_CUR: Input/output error");
  CHECK_FALSE(lepton.set(hal::kLeptonFpaTemperature, 1));
  CHECK(bolo::test::contains(lepton.last_error(), "SYS FPA temperature (XU unit 6, selector 6): SET_CUR: not a settable command"));
}

namespace {

// sysfs as uvcvideo lays it out: class/video4linux/videoN/device -> the USB interface, whose
// parent (the USB device) holds descriptors, idVendor, idProduct.
void fake_sysfs(const std::filesystem::path& root, const std::string& node, const std::vector<std::uint8_t>& descriptors,
                const std::string& vendor, const std::string& product) {
  const std::filesystem::path usb = root / "devices" / "usb1" / "1-1";
  std::filesystem::create_directories(usb / "1-1:1.0");
  std::filesystem::create_directories(root / "class" / "video4linux" / node);
  std::filesystem::create_directory_symlink(usb / "1-1:1.0", root / "class" / "video4linux" / node / "device");
  if (!descriptors.empty())
    std::ofstream(usb / "descriptors", std::ios::binary)
        .write(reinterpret_cast<const char*>(descriptors.data()), static_cast<std::streamsize>(descriptors.size()));
  std::ofstream(usb / "idVendor") << vendor << "\n";
  std::ofstream(usb / "idProduct") << product << "\n";
}

}  // namespace

TEST_CASE("a PureThermal node is told by its SYS extension unit, else by its USB ids", "[hal][purethermal]") {
  {
    bolo::test::TempDir sys;
    fake_sysfs(sys.path(), "video3", bolo::test::descriptors_with_extension_unit(6, "pt1-lep-sys-0000"), "1e4e", "0100");
    CHECK(hal::is_purethermal_node("/dev/video3", sys.path()));
    CHECK_FALSE(hal::is_purethermal_node("/dev/video4", sys.path()));  // no such node
  }
  {  // the ids, but no Lepton unit (a UVC gadget posing as one): its descriptors decide
    bolo::test::TempDir sys;
    fake_sysfs(sys.path(), "video3", bolo::test::descriptors_with_extension_unit(6, "another-unit-000"), "1e4e", "0100");
    CHECK_FALSE(hal::is_purethermal_node("/dev/video3", sys.path()));
  }
  {  // descriptors unreadable: the ids decide
    bolo::test::TempDir sys;
    fake_sysfs(sys.path(), "video3", {}, "1e4e", "0100");
    CHECK(hal::is_purethermal_node("/dev/video3", sys.path()));
    bolo::test::TempDir other;
    fake_sysfs(other.path(), "video3", {}, "046d", "0825");
    CHECK_FALSE(hal::is_purethermal_node("/dev/video3", other.path()));
  }
}

namespace {

class FakeControls final : public hal::V4l2Controls {
 public:
  std::vector<hal::V4l2Control> list() override {
    hal::V4l2Control gain;
    gain.id = 0x00980913;  // V4L2_CID_GAIN
    gain.name = "Gain";
    gain.maximum = 255;
    gain.step = 1;
    gain.default_value = 32;
    gain.value = 40;
    return {gain};
  }
  int set(std::uint32_t, std::int32_t) override { return 0; }
};

}  // namespace

TEST_CASE("bolo devices' readout: controls, and a PureThermal's temperatures through its extension unit",
          "[hal][purethermal]") {
  FakeControls controls;
  const hal::V4l2CameraReadout plain = hal::read_v4l2_camera(controls, nullptr);
  REQUIRE(plain.controls.size() == 1);
  CHECK(plain.controls[0].name == "Gain");
  CHECK(plain.controls[0].value == 40);
  CHECK_FALSE(plain.purethermal);
  CHECK_FALSE(plain.fpa_temp_mc);

  FakeUvcXu xu;
  xu.replies[{6, 6}] = {0x3F, 0x75};  // FPA 27.00 degC; AUX unanswered
  hal::PureThermalControls lepton("/dev/video7", xu);
  const hal::V4l2CameraReadout pt = hal::read_v4l2_camera(controls, &lepton);
  CHECK(pt.purethermal);
  CHECK(pt.fpa_temp_mc == 27000);
  CHECK_FALSE(pt.housing_temp_mc);
  REQUIRE(pt.errors.size() == 1);
  CHECK(bolo::test::contains(pt.errors[0], "/dev/video7: Lepton SYS AUX (housing) temperature (XU unit 6, selector 5)"));
}

TEST_CASE("a v4l2: spec's Lepton settings: the words parsed, then one SET_CUR each through the extension unit",
          "[hal][purethermal]") {
  hal::LeptonSettings s;
  CHECK(s.empty());
  CHECK(hal::parse_lepton_option({"gain", "auto"}, s));
  CHECK(hal::parse_lepton_option({"radiometry", "off"}, s));
  CHECK(hal::parse_lepton_option({"agc", "on"}, s));
  CHECK_FALSE(hal::parse_lepton_option({"format", "Y16"}, s));  // another key: not taken
  CHECK((s.gain_mode == 2u && s.radiometry == 0u && s.agc == 1u));
  CHECK(hal::parse_lepton_option({"gain", "high"}, s));
  CHECK(s.gain_mode == 0u);
  CHECK(hal::parse_lepton_option({"gain", "low"}, s));
  CHECK(s.gain_mode == 1u);
  CHECK_THROWS_WITH(hal::parse_lepton_option({"radiometry", "yes"}, s), "'radiometry=yes': expected radiometry=off|on");

  FakeUvcXu xu;
  hal::PureThermalControls lepton("/dev/video7", xu);
  CHECK(lepton.apply(s));
  REQUIRE(xu.log.size() == 3);
  // Gain mode low: SYS unit 6, selector 19; radiometry off: RAD 5/5; AGC on: AGC 3/1. Two words each.
  CHECK((xu.log[0].unit == 6 && xu.log[0].selector == 19 && xu.log[0].request == hal::UvcRequest::set_cur));
  CHECK(xu.log[0].data == std::vector<std::uint8_t>{1, 0, 0, 0});
  CHECK((xu.log[1].unit == 5 && xu.log[1].selector == 5 && xu.log[1].data == std::vector<std::uint8_t>{0, 0, 0, 0}));
  CHECK((xu.log[2].unit == 3 && xu.log[2].selector == 1 && xu.log[2].data == std::vector<std::uint8_t>{1, 0, 0, 0}));

  xu.log.clear();
  CHECK(lepton.apply({.agc = 0}));  // only what is given
  REQUIRE(xu.log.size() == 1);
  CHECK(xu.log[0].unit == 3);
  xu.refuse = EIO;
  CHECK_FALSE(lepton.apply(s));  // the first refusal stops it
  CHECK(xu.log.size() == 2);
  CHECK(lepton.last_error() == "/dev/video7: Lepton SYS gain mode (XU unit 6, selector 19): SET_CUR: Input/output error");
}
