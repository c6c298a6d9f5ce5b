#include "bolo/hal/uvc_controls.hpp"

#include <fcntl.h>
#include <linux/usb/video.h>
#include <linux/uvcvideo.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "xioctl.hpp"

namespace bolo::hal {
namespace {

static_assert(static_cast<int>(UvcRequest::set_cur) == UVC_SET_CUR && static_cast<int>(UvcRequest::get_cur) == UVC_GET_CUR &&
              static_cast<int>(UvcRequest::get_len) == UVC_GET_LEN && static_cast<int>(UvcRequest::get_info) == UVC_GET_INFO);

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string text;
  in >> text;
  return text;
}

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

V4l2NodeControls::V4l2NodeControls(std::string node) : node_(std::move(node)) {
  fd_ = ::open(node_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(node_ + ": cannot open for controls: " + std::strerror(errno));
}

V4l2NodeControls::~V4l2NodeControls() {
  if (fd_ >= 0) ::close(fd_);
}

int V4l2NodeControls::query(std::uint8_t unit, std::uint8_t selector, UvcRequest request,
                            std::span<std::uint8_t> data) {
  uvc_xu_control_query q{};
  q.unit = unit;
  q.selector = selector;
  q.query = static_cast<std::uint8_t>(request);
  q.size = static_cast<std::uint16_t>(data.size());
  q.data = data.data();
  return xioctl(fd_, UVCIOC_CTRL_QUERY, &q) == 0 ? 0 : errno;
}

std::vector<V4l2Control> V4l2NodeControls::list() {
  std::vector<V4l2Control> out;
  v4l2_queryctrl q{};
  q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
  while (xioctl(fd_, VIDIOC_QUERYCTRL, &q) == 0) {
    const bool plain = q.type == V4L2_CTRL_TYPE_INTEGER || q.type == V4L2_CTRL_TYPE_BOOLEAN ||
                       q.type == V4L2_CTRL_TYPE_MENU || q.type == V4L2_CTRL_TYPE_INTEGER_MENU;
    if (plain && !(q.flags & V4L2_CTRL_FLAG_DISABLED)) {
      V4l2Control c;
      c.id = q.id;
      c.name = reinterpret_cast<const char*>(q.name);
      c.minimum = q.minimum;
      c.maximum = q.maximum;
      c.step = q.step;
      c.default_value = q.default_value;
      c.read_only = (q.flags & V4L2_CTRL_FLAG_READ_ONLY) != 0;
      v4l2_control value{q.id, 0};
      if (!(q.flags & V4L2_CTRL_FLAG_WRITE_ONLY) && xioctl(fd_, VIDIOC_G_CTRL, &value) == 0) c.value = value.value;
      out.push_back(std::move(c));
    }
    q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
  }
  return out;
}

int V4l2NodeControls::set(std::uint32_t id, std::int32_t value) {
  v4l2_control c{id, value};
  return xioctl(fd_, VIDIOC_S_CTRL, &c) == 0 ? 0 : errno;
}

bool PureThermalControls::fail(const LeptonXuCommand& command, const char* request, const std::string& why) {
  last_error_ = node_ + ": Lepton " + command.name + " (XU unit " +
                std::to_string(purethermal_xu_unit(command.command_id)) + ", selector " +
                std::to_string(purethermal_xu_selector(command.command_id)) + "): " + request + ": " + why;
  return false;
}

bool PureThermalControls::set(const LeptonXuCommand& command, std::uint32_t value) {
  std::array<std::uint8_t, 4> data{};
  const std::size_t length = encode_purethermal_set(command, value, data);
  if (length == 0) return fail(command, "SET_CUR", "not a settable command");
  const int error = xu_.query(purethermal_xu_unit(command.command_id), purethermal_xu_selector(command.command_id),
                              UvcRequest::set_cur, std::span<std::uint8_t>(data.data(), length));
  return error == 0 || fail(command, "SET_CUR", std::strerror(error));
}

bool PureThermalControls::apply(const LeptonSettings& settings) {
  return (!settings.gain_mode || set(kLeptonGainMode, *settings.gain_mode)) &&
         (!settings.radiometry || set(kLeptonRadiometry, *settings.radiometry)) &&
         (!settings.agc || set(kLeptonAgc, *settings.agc));
}

std::optional<std::int32_t> PureThermalControls::get(const LeptonXuCommand& command) {
  std::array<std::uint8_t, 4> data{};
  const std::size_t length = purethermal_xu_length(command);
  const int error = xu_.query(purethermal_xu_unit(command.command_id), purethermal_xu_selector(command.command_id),
                              UvcRequest::get_cur, std::span<std::uint8_t>(data.data(), length));
  if (error != 0) {
    fail(command, "GET_CUR", std::strerror(error));
    return std::nullopt;
  }
  const auto value = decode_purethermal_reply(command, std::span<const std::uint8_t>(data.data(), length));
  if (!value) fail(command, "GET_CUR", "no reading in the reply");
  return value;
}

bool is_purethermal_node(const std::string& node, const std::filesystem::path& sysfs) {
  std::error_code ec;
  const std::filesystem::path name = std::filesystem::path(node).filename();
  // device -> the USB interface; its parent holds the device's descriptors and ids.
  const std::filesystem::path interface =
      std::filesystem::canonical(sysfs / "class" / "video4linux" / name / "device", ec);
  if (ec) return false;
  const std::filesystem::path usb = interface.parent_path();
  const std::vector<std::uint8_t> descriptors = read_bytes(usb / "descriptors");
  if (!descriptors.empty()) return has_purethermal_sys_unit(descriptors);
  return read_text(usb / "idVendor") == "1e4e" && read_text(usb / "idProduct") == "0100";
}

std::function<bool()> v4l2_shutter_command(const std::string& node, bool purethermal,
                                           const std::shared_ptr<UvcExtensionUnit>& xu) {
  if (!purethermal || !xu) return {};
  auto lepton = std::make_shared<PureThermalControls>(node, *xu);
  return [lepton, xu] { return lepton->run_ffc(); };
}

V4l2CameraReadout read_v4l2_camera(V4l2Controls& controls, PureThermalControls* lepton) {
  V4l2CameraReadout r;
  r.controls = controls.list();
  if (!lepton) return r;
  r.purethermal = true;
  r.fpa_temp_mc = lepton->get(kLeptonFpaTemperature);
  if (!r.fpa_temp_mc) r.errors.push_back(lepton->last_error());
  r.housing_temp_mc = lepton->get(kLeptonHousingTemperature);
  if (!r.housing_temp_mc) r.errors.push_back(lepton->last_error());
  return r;
}

}  // namespace bolo::hal
