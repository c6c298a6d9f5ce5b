// bolo capture and bolo devices, without hardware: from a recording (file:), from the real FLIR
// ONE transfer log through the USB source (flirone-log:), and every refusal of docs/errors.md §8.

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "../hal/fake_uvc_xu.hpp"
#include "../hal/flirone_frames.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/hal/uvc_controls.hpp"
#include "cli_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

namespace {

std::string hex(const std::vector<std::uint8_t>& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string s;
  for (auto b : bytes) {
    s += digits[b >> 4];
    s += digits[b & 15];
  }
  return s;
}

// A transfer log of `frames` FLIR ONE frames, each one transfer; `corrupt` flips a pixel bit.
void write_log(const fs::path& dir, int frames, bool corrupt) {
  fs::create_directories(dir);
  for (int i = 0; i < frames; ++i) {
    auto f = make_flirone_frame({.frame_counter = static_cast<std::uint32_t>(3 * i)});
    if (corrupt) f[1000] ^= 0x10;
    std::ofstream(dir / (std::to_string(i + 1) + ".txt")) << hex(f);
  }
}

}  // namespace

// A V4L2 camera as the v4l2: backend makes it (v4l2_shutter_command), over a recording and a
// fake extension unit: scheme "fake-v4l2-purethermal" is a PureThermal, "fake-v4l2-other" not.
std::shared_ptr<FakeUvcXu> register_fake_v4l2(const std::string& scheme, bool purethermal) {
  auto xu = std::make_shared<FakeUvcXu>();
  hal::SourceBackend b;
  b.scheme = scheme;
  b.argument = "REC";
  b.summary = "a recording as a V4L2 camera (tests)";
  b.open = [xu, purethermal](const std::string& rec, const hal::SourceOptions&) {
    return std::make_unique<hal::OpenedSource>(hal::open_source("file:" + rec), "fake V4L2", nullptr,
                                               hal::v4l2_shutter_command("/dev/video7", purethermal, xu));
  };
  hal::register_source(b);
  return xu;
}

TEST_CASE("capture: --shutter-at on a PureThermal sends Lepton SYS Run FFC, once per request", "[cli][capture]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const auto xu = register_fake_v4l2("fake-v4l2-purethermal", true);
  const CliResult r = run_bolo({"capture", "--device", "fake-v4l2-purethermal:" + (tmp / "rec").string(), "--out",
                                (tmp / "out").string(), "--frames", "6", "--shutter-at", "2", "--no-progress"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "shutter events requested: 1 of 1"));
  REQUIRE(xu->log.size() == 1);
  CHECK(xu->log[0].unit == 6);
  CHECK(xu->log[0].selector == 17);
  CHECK(xu->log[0].request == hal::UvcRequest::set_cur);
  CHECK(xu->log[0].data.size() == 1);
}

TEST_CASE("capture: another V4L2 camera has no shutter, --shutter-at is refused", "[cli][capture]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const auto xu = register_fake_v4l2("fake-v4l2-other", false);
  const std::string device = "fake-v4l2-other:" + (tmp / "rec").string();
  CHECK(contains(refused({"capture", "--device", device, "--out", (tmp / "out").string(), "--frames", "6", "--shutter-at", "2"}),
                 "--shutter-at: " + device + " has no shutter control here"));
  CHECK(xu->log.empty());
  CHECK_FALSE(fs::exists(tmp / "out"));
}

TEST_CASE("capture: file: re-records a recording frame for frame", "[cli][capture]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const CliResult r = run_bolo({"capture", "--device", "file:" + (tmp / "rec").string(), "--out",
                                (tmp / "out").string(), "--no-progress"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "captured 12 frames (24x16)"));
  rec::Recording in(tmp / "rec"), out(tmp / "out");
  REQUIRE(out.frame_count() == 12);
  for (std::uint64_t i = 0; i < 12; ++i) {
    CHECK(read_u16_frame(out, i) == read_u16_frame(in, i));
    const rec::FrameRow& a = in.rows()[i];
    const rec::FrameRow& b = out.rows()[i];
    CHECK(*b.t_s == Approx(*a.t_s - *in.rows()[0].t_s).margin(1e-9));
    CHECK(*b.exposure_s == Approx(*a.exposure_s).margin(1e-9));
    CHECK(*b.readout_s == Approx(*a.readout_s).margin(1e-9));
    CHECK(b.ffc == a.ffc);
  }
  CHECK(out.info().width == 24);
  // A recording counts nothing beyond SourceStats: no line for it, an empty object.
  CHECK_FALSE(contains(r.out, "device counters"));
  const auto summary = nlohmann::json::parse(read_text(tmp / "out" / "capture.json"));
  CHECK(summary.at("extra_counters") == nlohmann::json::object());
}

TEST_CASE("capture: --frames stops early, the source ending first is reported", "[cli][capture]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  CliResult r = run_bolo({"capture", "--device", "file:" + (tmp / "rec").string(), "--out",
                          (tmp / "five").string(), "--frames", "5"});
  REQUIRE(r.code == 0);
  CHECK(rec::Recording(tmp / "five").frame_count() == 5);
  r = run_bolo({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", (tmp / "all").string(),
                "--frames", "50"});
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "the source ended after 12 of 50 frames"));
}

TEST_CASE("capture: the real FLIR ONE transfer log gives the shared recording", "[cli][capture][real]") {
  const fs::path log = shared_folder("usb/flirone-pro", "1.txt");
  if (log.empty()) return;
  const fs::path ref = shared_recording("flirone-lepton-telemetry");
  TempDir tmp;
  const CliResult r = run_bolo({"capture", "--device", "flirone-log:" + log.string(), "--out", (tmp / "out").string()});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "captured 20 frames (80x60)"));
  CHECK(contains(r.out, "duplicates 2"));
  CHECK(contains(r.out, "device counters: skipped in camera 0, counter jumps 0,"));
  CHECK(read_text(tmp / "out" / "frames.npy") == read_text(ref / "frames.npy"));  // byte for byte
  rec::Recording out(tmp / "out"), expected(ref);
  for (std::uint64_t i = 0; i < 20; ++i) {
    const rec::FrameRow& a = expected.rows()[i];
    const rec::FrameRow& b = out.rows()[i];
    CHECK(*b.t_s == Approx(*a.t_s).margin(1e-9));
    CHECK(*b.fpa_temp_c == Approx(*a.fpa_temp_c).margin(1e-9));
    CHECK(*b.housing_temp_c == Approx(*a.housing_temp_c).margin(1e-9));
    CHECK(b.ffc == a.ffc);
  }
}

TEST_CASE("capture: a source's extra counters are in the summary and in capture.json", "[cli][capture]") {
  TempDir tmp;
  const fs::path log = tmp / "log";
  fs::create_directories(log);
  std::ofstream(log / "1.txt") << "01020304";  // joined mid-frame: a stray transfer
  const std::uint32_t counters[] = {0, 3, 9};   // the core steps by 3: 6 was skipped in the camera
  for (std::uint32_t i = 0; i < 3; ++i)
    std::ofstream(log / (std::to_string(i + 2) + ".txt")) << hex(make_flirone_frame({.frame_counter = counters[i]}));
  const CliResult r = run_bolo({"capture", "--device", "flirone-log:" + log.string(), "--out", (tmp / "out").string()});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "captured 3 frames (80x60)"));
  CHECK(contains(r.out,
            "\ndevice counters: skipped in camera 1, counter jumps 0, stray transfers 1, trailing bytes 0, bad status 0\n"));
  const auto summary = nlohmann::json::parse(read_text(tmp / "out" / "capture.json"));
  CHECK(summary.at("extra_counters") == nlohmann::json({{"skipped_in_camera", 1},
                                                        {"counter_jumps", 0},
                                                        {"stray_transfers", 1},
                                                        {"trailing_bytes", 0},
                                                        {"bad_status", 0}}));
}

TEST_CASE("capture: refusals name the device, flag or file and leave nothing behind", "[cli][capture]") {
  TempDir tmp;
  SmallRecording::write(tmp / "rec");
  const auto before = entries(tmp.path());
  const std::string out = (tmp / "out").string();
  CHECK(contains(refused({"capture", "--device", "webcam", "--out", out, "--frames", "1"}),
            "--device webcam: unknown device (expected v4l2:/dev/videoN, usb:flirone, usb:seek, file:REC or flirone-log:DIR)"));
  CHECK(contains(refused({"capture", "--device", "usb:boson", "--out", out, "--frames", "1"}),
            "--device usb:boson: unknown USB camera 'boson'"));
  CHECK(contains(refused({"capture", "--device", "v4l2:", "--out", out, "--frames", "1"}),
            "--device v4l2:: v4l2: needs a device node"));
  CHECK(contains(refused({"capture", "--device", "file:", "--out", out}), "--device file:: file: needs a recording folder"));
  CHECK(contains(refused({"capture", "--device", "flirone-log:", "--out", out}),
            "--device flirone-log:: flirone-log: needs a transfer-log folder"));
  CHECK(contains(refused({"capture", "--device", "v4l2:/dev/null", "--out", out}),
            "--frames: required for a live camera (v4l2:/dev/null)"));
  CHECK(contains(refused({"capture", "--device", "v4l2:/dev/null", "--out", out, "--frames", "3"}),
            "--device v4l2:/dev/null: /dev/null: not a V4L2 device"));
  CHECK(contains(refused({"capture", "--device", "v4l2:/nonexistent/video3", "--out", out, "--frames", "3"}),
            "/nonexistent/video3: cannot open: No such file or directory"));
  const std::string usb = refused({"capture", "--device", "usb:flirone", "--out", out, "--frames", "3"});
#if defined(BOLO_HAVE_LIBUSB)
  CHECK(contains(usb, "--device usb:flirone: usb 09cb:1996: no device"));
  CHECK(contains(refused({"capture", "--device", "usb:seek", "--out", out, "--frames", "3"}),
            "--device usb:seek: usb 289d:0010/0011: no device"));
#else
  CHECK(contains(usb, "this build has no USB backend"));
#endif
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "none").string(), "--out", out}), "none"));
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", (tmp / "rec").string()}),
            "exists (use --overwrite to replace it)"));
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", out, "--gpio", "gpiochip0"}),
            "--gpio gpiochip0: no lines given"));
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", out, "--gpio",
                     "gpiochip0:sync=x"}),
            "--gpio gpiochip0:sync=x: sync=x: expected a line number 0..4095"));
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", out, "--gpio",
                     "gpiochip0:led=3"}),
            "'led=3': expected sync=N, shutter=N or imminent=N"));
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", out, "--shutter-at", "3"}),
            "--shutter-at: file:" + (tmp / "rec").string() + " has no shutter control here (use --gpio CHIP:shutter=N, usb:seek, or a PureThermal on v4l2:)"));
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", out, "--shutter-at", "-2"}),
            "--shutter-at: must not be negative, got -2"));
#if defined(BOLO_HAVE_LIBGPIOD)
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", out, "--gpio",
                     "bolo-no-such-chip:sync=3"}),
            "--gpio bolo-no-such-chip:sync=3: gpio bolo-no-such-chip: cannot open the chip"));
#else
  CHECK(contains(refused({"capture", "--device", "file:" + (tmp / "rec").string(), "--out", out, "--gpio",
                     "gpiochip0:sync=3"}),
            "this build has no GPIO backend"));
#endif
  CHECK(entries(tmp.path()) == before);
}

TEST_CASE("capture: transfer logs that are not logs, and a device that only faults", "[cli][capture]") {
  TempDir tmp;
  const std::string out = (tmp / "out").string();
  fs::create_directories(tmp / "empty");
  CHECK(contains(refused({"capture", "--device", "flirone-log:" + (tmp / "empty").string(), "--out", out}),
            "no transfer files (1.txt, 2.txt, ...)"));
  fs::create_directories(tmp / "gap");
  std::ofstream(tmp / "gap" / "1.txt") << "efbe";
  std::ofstream(tmp / "gap" / "3.txt") << "efbe";
  CHECK(contains(refused({"capture", "--device", "flirone-log:" + (tmp / "gap").string(), "--out", out}),
            "transfer 2.txt missing"));
  fs::create_directories(tmp / "nothex");
  std::ofstream(tmp / "nothex" / "1.txt") << "efbe00zz";
  CHECK(contains(refused({"capture", "--device", "flirone-log:" + (tmp / "nothex").string(), "--out", out}),
            "1.txt: offset 6: not a hex digit"));
  write_log(tmp / "bad", 6, true);
  const std::string gave_up = refused({"capture", "--device", "flirone-log:" + (tmp / "bad").string(), "--out", out,
                                       "--max-faults", "3"});
  CHECK(contains(gave_up, "gave up after 3 faults in a row, 0 frames captured, nothing written (timeouts 0, short 0, corrupt 4"));
  // The FLIR ONE source's own counters follow the common ones.
  CHECK(contains(gave_up, "; device counters: "));
  CHECK(contains(gave_up, "skipped in camera 0"));
  write_log(tmp / "worse", 2, true);
  CHECK(contains(refused({"capture", "--device", "flirone-log:" + (tmp / "worse").string(), "--out", out}),
            "delivered no frames, nothing written"));
  CHECK_FALSE(fs::exists(out));
  // Good frames around faults: captured, faults counted.
  write_log(tmp / "good", 3, false);
  const CliResult r = run_bolo({"capture", "--device", "flirone-log:" + (tmp / "good").string(), "--out", out});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "captured 3 frames (80x60)"));
  // The synthetic frames all carry the same camera time: kept, their t_s left empty.
  CHECK(contains(r.out, "2 frames with a time stamp not after the previous one: t_s left empty"));
  rec::Recording rec(out);
  CHECK(rec.rows()[0].t_s == 0.0);
  CHECK_FALSE(rec.rows()[1].t_s.has_value());
}

TEST_CASE("devices: lists the three kinds and says which backends this build has", "[cli][devices]") {
  CliResult r = run_bolo({"devices"});
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "V4L2 (Y16 counts; GREY, YUYV, UYVY: 8-bit tone-mapped):"));
  CHECK(contains(r.out, "USB:"));
  CHECK(contains(r.out, "GPIO:"));
  r = run_bolo({"devices", "--json"});
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["backends"]["v4l2"] == true);
#if defined(BOLO_HAVE_LIBUSB)
  CHECK(j["backends"]["usb"] == true);
#else
  CHECK(j["backends"]["usb"] == false);
#endif
  CHECK(j["v4l2"].is_array());
  r = run_bolo({"devices", "--help"});
  CHECK(r.code == 0);
  CHECK(contains(r.out, "compiled out"));
  r = run_bolo({"capture", "--help"});
  CHECK(r.code == 0);
  CHECK(contains(r.out, "flirone-log:DIR"));
}
