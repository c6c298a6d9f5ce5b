// HIL test of a PureThermal's Lepton command interface through the real uvcvideo driver
// (UVCIOC_CTRL_QUERY on its extension units) and the project's own HAL code, against the
// emulator (uvc_emulator on the patched usb_f_uvc):
// 1) the node is a PureThermal by its descriptors (is_purethermal_node), and each command bolo
//    sends has its control in its unit's bmControls, under the unit's "pt1-lep-<module>-0000" GUID;
// 2) FPA and housing (AUX) temperatures read are the emulator's (26.85 / 28.35 degC), gain mode
//    reads back high (the factory default);
// 3) the source opened as `v4l2:NODE?gain=low,radiometry=off,agc=on` (the registry, as `bolo
//    capture --device` opens it) has set them: read back 1, 0, 1;
// 4) streaming from it, the source's shutter (SYS Run FFC) requested before frame K shows as the
//    one FFC in the frame headers, in the frame the emulator says it put it in (its --xu-log
//    "ffc INDEX COUNTER", matched by telemetry counter), K <= INDEX <= K + 16 (frames made before
//    the emulator took the request: its --credit 3 and a batch of its buffers), no frame dropped.
// Any refusal fails with the HAL's message (exit 1): an emulator told to refuse must fail it.
//
//   hil_uvc_xu --xu-log FILE --frames N --shutter-at K [--progress FILE] [--device /dev/videoN]

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bolo/hal/lepton_telemetry.hpp"
#include "bolo/hal/source_registry.hpp"
#include "bolo/hal/uvc_controls.hpp"
#include "bolo/hal/v4l2_source.hpp"
#include "emulators/whole_number.hpp"
#include "uvc_node.hpp"

namespace {

using namespace bolo;
using Clock = std::chrono::steady_clock;

int failures = 0;
void expect(bool ok, const std::string& what) {
  if (ok) return;
  ++failures;
  std::printf("hil_uvc_xu: FAIL %s\n", what.c_str());
}

// The USB device's descriptors (sysfs) the node belongs to.
std::vector<std::uint8_t> usb_descriptors(const std::string& node) {
  const std::filesystem::path interface = std::filesystem::canonical(
      std::filesystem::path("/sys/class/video4linux") / std::filesystem::path(node).filename() / "device");
  std::ifstream in(interface.parent_path() / "descriptors", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Whether an extension unit `unit` with the module's GUID, one input pin, declares `selector`.
bool declares(const std::vector<std::uint8_t>& d, std::uint8_t unit, std::uint8_t selector) {
  const auto guid = hal::purethermal_xu_guid(unit);
  for (std::size_t at = 0; guid && at + 2 <= d.size() && d[at] >= 2; at += d[at]) {
    const std::size_t length = d[at];
    // bLength, CS_INTERFACE, VC_EXTENSION_UNIT, bUnitID, GUID[16], bNumControls, bNrInPins (1),
    // baSourceID, bControlSize, bmControls...
    if (at + length > d.size() || length < 26 || d[at + 1] != 0x24 || d[at + 2] != 0x06 || d[at + 3] != unit) continue;
    if (!std::equal(guid->begin(), guid->end(), d.begin() + static_cast<std::ptrdiff_t>(at + 4)) || d[at + 21] != 1)
      return false;
    const std::size_t control_size = d[at + 23];
    const std::size_t bit = selector - 1u;
    return bit / 8 < control_size && 24 + control_size < length && (d[at + 24 + bit / 8] >> (bit % 8)) & 1u;
  }
  return false;
}

class FfcSink final : public fw::LineSink {
 public:
  void begin_frame(const fw::FrameHeader& header) override { ffc_ = header.ffc == fw::FfcState::completed; }
  void push_line(std::uint32_t, fw::LineView) override {}
  void end_frame() override { frames.push_back(ffc_); }
  std::vector<bool> frames;  // FFC completed in this frame

 private:
  bool ffc_ = false;
};

// The emulator's "ffc INDEX COUNTER" lines.
std::vector<std::pair<std::uint64_t, std::uint32_t>> emulator_ffcs(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> out;
  std::string word;
  while (in >> word) {
    if (word != "ffc") {
      std::getline(in, word);
      continue;
    }
    std::uint64_t index = 0;
    std::uint32_t counter = 0;
    in >> index >> counter;
    out.emplace_back(index, counter);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string xu_log, progress, node;
    std::uint64_t frames = 0, shutter_at = 0;
    for (int i = 1; i + 1 < argc; i += 2) {
      const std::string a = argv[i], v = argv[i + 1];
      if (a == "--xu-log") xu_log = v;
      else if (a == "--progress") progress = v;
      else if (a == "--device") node = v;
      else if (a == "--frames") frames = hil::whole_number(a, v);
      else if (a == "--shutter-at") shutter_at = hil::whole_number(a, v);
      else throw std::runtime_error("unknown option " + a);
    }
    if (argc % 2 == 0) throw std::runtime_error(std::string(argv[argc - 1]) + " needs a value");
    if (xu_log.empty() || frames == 0 || shutter_at >= frames)
      throw std::runtime_error("give --xu-log FILE --frames N --shutter-at K (K < N)");
    if (node.empty()) node = hil::find_uvc_node();

    // 1) Detection and the descriptors.
    expect(hal::is_purethermal_node(node), node + ": not detected as a PureThermal (no Lepton SYS unit in its descriptors)");
    const std::vector<std::uint8_t> descriptors = usb_descriptors(node);
    for (const hal::LeptonXuCommand& c : hal::kLeptonXuCommands)
      expect(declares(descriptors, hal::purethermal_xu_unit(c.command_id), hal::purethermal_xu_selector(c.command_id)),
             std::string(c.name) + ": no such control in the extension unit's descriptor");
    if (failures > 0) return 1;

    // 2) Readings through the HAL's PureThermalControls.
    hal::V4l2NodeControls controls(node);
    hal::PureThermalControls lepton(node, controls);
    auto read = [&](const hal::LeptonXuCommand& c, std::int32_t want) {
      const std::optional<std::int32_t> got = lepton.get(c);
      if (!got) expect(false, lepton.last_error());
      else expect(*got == want, std::string(c.name) + ": read " + std::to_string(*got) + ", want " + std::to_string(want));
    };
    read(hal::kLeptonFpaTemperature, hal::centikelvin_to_mc(30000));
    read(hal::kLeptonHousingTemperature, hal::centikelvin_to_mc(30150));
    read(hal::kLeptonGainMode, 0);
    if (failures > 0) return 1;

    // 3) The spec's settings, applied when the registry opens the camera.
    const std::string spec = "v4l2:" + node + "?gain=low,radiometry=off,agc=on";
    const std::unique_ptr<hal::OpenedSource> source = hal::open_source(spec);
    read(hal::kLeptonGainMode, 1);
    read(hal::kLeptonRadiometry, 0);
    read(hal::kLeptonAgc, 1);
    expect(source->has_shutter(), spec + ": no shutter command");
    if (failures > 0) return 1;

    // 4) The shutter in the stream.
    const int progress_fd = progress.empty() ? -1 : ::open(progress.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    FfcSink sink;
    const auto& v4l2 = dynamic_cast<const hal::V4l2Source&>(source->backend());
    std::vector<std::uint32_t> counters;  // each delivered frame's telemetry frame counter
    auto last_frame = Clock::now();
    std::optional<std::size_t> requested_at;
    while (sink.frames.size() < frames && Clock::now() - last_frame < std::chrono::seconds(5)) {
      if (!requested_at && sink.frames.size() == shutter_at) {
        requested_at = sink.frames.size();
        expect(source->request_shutter(), "the source's shutter (SYS Run FFC) was refused");
      }
      const std::size_t before = sink.frames.size();
      source->stream_frame(sink);
      if (sink.frames.size() == before) continue;
      counters.push_back(v4l2.last_telemetry().frame_counter);
      last_frame = Clock::now();
      if (progress_fd >= 0) {
        const std::string text = std::to_string(sink.frames.size()) + "\n";
        if (::pwrite(progress_fd, text.data(), text.size(), 0) < 0) throw std::runtime_error(progress + ": write failed");
      }
    }
    expect(sink.frames.size() == frames,
           "delivered " + std::to_string(sink.frames.size()) + " of " + std::to_string(frames) + " frames");
    expect(v4l2.negotiated().telemetry_rows > 0, "no telemetry rows negotiated: no FFC to see");
    expect(source->stats().dropped == 0, std::to_string(source->stats().dropped) + " frames dropped");
    std::vector<std::uint32_t> seen;  // counters of the frames with an FFC
    for (std::size_t i = 0; i < sink.frames.size(); ++i)
      if (sink.frames[i]) seen.push_back(counters[i]);
    const auto sent = emulator_ffcs(xu_log);
    expect(sent.size() == 1, "the emulator ran " + std::to_string(sent.size()) + " FFCs, want 1");
    expect(seen.size() == 1, std::to_string(seen.size()) + " frames with an FFC in their header, want 1");
    if (sent.size() == 1 && seen.size() == 1) {
      // By the telemetry counter: uvcvideo may swap two frames' order under load.
      expect(seen[0] == sent[0].second, "FFC in the frame of counter " + std::to_string(seen[0]) +
                                            ", the emulator put it in counter " + std::to_string(sent[0].second));
      expect(sent[0].first >= shutter_at && sent[0].first <= shutter_at + 16,
             "FFC in frame " + std::to_string(sent[0].first) + ", requested before frame " + std::to_string(shutter_at));
    }
    std::uint32_t highest = 0;
    for (std::uint32_t c : counters) highest = std::max(highest, c);
    expect(highest == frames, "highest telemetry frame counter " + std::to_string(highest) + ", want " +
                                  std::to_string(frames) + " (the delivered frames are the sent ones)");
    std::printf("hil_uvc_xu: %s: %s is a PureThermal by its descriptors; FPA / AUX read, gain low, radiometry off, "
                "AGC on read back; Run FFC requested before frame %llu shown in the frame of counter %s (of %zu)\n",
                failures == 0 ? "PASS" : "FAIL", node.c_str(), static_cast<unsigned long long>(shutter_at),
                seen.empty() ? "(none)" : std::to_string(seen[0]).c_str(), sink.frames.size());
    return failures == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("hil_uvc_xu: FAIL %s\n", e.what());
    return 1;
  }
}
