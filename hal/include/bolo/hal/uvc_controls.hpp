#pragma once
// A V4L2 camera's controls: plain V4L2 controls (VIDIOC_QUERYCTRL, G_CTRL, S_CTRL) and UVC
// extension-unit requests (UVCIOC_CTRL_QUERY), each behind an interface tests can fake, and the
// Lepton commands of a PureThermal board over the latter (purethermal_xu.hpp): readings, the
// settings a v4l2: spec asks for (device_spec.hpp), Run FFC as the shutter. Unit-tested against a
// fake extension unit, and in the HIL VM through uvcvideo against the emulated board
// (tests/hil/hil_uvc_xu.cpp). Host code: opening throws std::runtime_error naming the node; a
// refused request is returned, never thrown.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bolo/hal/device_spec.hpp"
#include "bolo/hal/purethermal_xu.hpp"

namespace bolo::hal {

// UVC extension-unit controls of one device.
class UvcExtensionUnit {
 public:
  virtual ~UvcExtensionUnit() = default;
  // One request; `data` is what is sent (SET_CUR) or filled (GET_*). 0, or the errno it failed with.
  virtual int query(std::uint8_t unit, std::uint8_t selector, UvcRequest request, std::span<std::uint8_t> data) = 0;
};

struct V4l2Control {
  std::uint32_t id = 0;
  std::string name;
  std::int32_t minimum = 0, maximum = 0, step = 0, default_value = 0;
  std::optional<std::int32_t> value;  // nothing when G_CTRL refused (a write-only or inactive control)
  bool read_only = false;
};

// Plain V4L2 controls of one device node.
class V4l2Controls {
 public:
  virtual ~V4l2Controls() = default;
  // The node's user controls (integer, boolean, menu), in the driver's order.
  virtual std::vector<V4l2Control> list() = 0;
  // 0, or the errno S_CTRL failed with.
  virtual int set(std::uint32_t id, std::int32_t value) = 0;
};

// Both over a file descriptor of its own on the node (controls work beside a streaming one).
class V4l2NodeControls final : public UvcExtensionUnit, public V4l2Controls {
 public:
  explicit V4l2NodeControls(std::string node);
  ~V4l2NodeControls() override;
  V4l2NodeControls(const V4l2NodeControls&) = delete;
  V4l2NodeControls& operator=(const V4l2NodeControls&) = delete;
  int query(std::uint8_t unit, std::uint8_t selector, UvcRequest request, std::span<std::uint8_t> data) override;
  std::vector<V4l2Control> list() override;
  int set(std::uint32_t id, std::int32_t value) override;
  const std::string& node() const { return node_; }

 private:
  std::string node_;
  int fd_ = -1;
};

// The Lepton commands through a PureThermal's extension units. Each failure keeps a message naming
// the node, the command and its unit / selector: "/dev/video0: Lepton SYS Run FFC (XU unit 6,
// selector 17): SET_CUR: Broken pipe".
class PureThermalControls {
 public:
  PureThermalControls(std::string node, UvcExtensionUnit& xu) : node_(std::move(node)), xu_(xu) {}
  // SYS Run FFC: the shutter closes and the core recalibrates. False when refused (last_error()).
  bool run_ffc() { return set(kLeptonRunFfc, 0); }
  bool set(const LeptonXuCommand& command, std::uint32_t value);
  // SET_CUR of each setting given: gain mode, radiometry, AGC, in that order. False at the first
  // refusal (last_error()); the ones before it stay set.
  bool apply(const LeptonSettings& settings);
  // GET_CUR decoded (purethermal_xu.hpp); nothing when refused or unreadable (last_error()).
  std::optional<std::int32_t> get(const LeptonXuCommand& command);
  const std::string& last_error() const { return last_error_; }

 private:
  bool fail(const LeptonXuCommand& command, const char* request, const std::string& why);

  std::string node_;
  UvcExtensionUnit& xu_;
  std::string last_error_;
};

// Whether the V4L2 node belongs to a PureThermal: its USB device's descriptors (sysfs) have the
// Lepton SYS extension unit, or (descriptors unreadable) its ids are 1e4e:0100. `sysfs` is the
// root the node's class/video4linux/<name>/device link is looked up under.
bool is_purethermal_node(const std::string& node, const std::filesystem::path& sysfs = "/sys");

// The shutter command a V4L2 camera offers: Lepton SYS Run FFC through `xu` on a PureThermal,
// none on another camera. `xu` is kept alive by the function.
std::function<bool()> v4l2_shutter_command(const std::string& node, bool purethermal,
                                           const std::shared_ptr<UvcExtensionUnit>& xu);

// What `bolo devices` shows of a V4L2 camera: its controls and, on a PureThermal (`lepton` given),
// the FPA and housing (AUX) temperatures read through the extension unit.
struct V4l2CameraReadout {
  std::vector<V4l2Control> controls;
  bool purethermal = false;
  std::optional<std::int32_t> fpa_temp_mc, housing_temp_mc;  // nothing when not read
  std::vector<std::string> errors;                            // PureThermalControls::last_error() of each failure
};
V4l2CameraReadout read_v4l2_camera(V4l2Controls& controls, PureThermalControls* lepton);

}  // namespace bolo::hal
