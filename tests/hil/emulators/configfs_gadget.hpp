#pragma once
// A USB gadget made through the kernel's configfs (libcomposite): device identity, one
// configuration, functions linked into it, and binding to / unbinding from a UDC (unplug and
// replug as the host sees it).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace bolo::hil {

struct GadgetIdentity {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  std::uint16_t bcd_device = 0x0100;
  std::string manufacturer;
  std::string product;
  std::string serial;
  std::uint8_t device_class = 0;  // 0: per interface; 0xEF/2/1: IAD (UVC)
  std::uint8_t device_subclass = 0;
  std::uint8_t device_protocol = 0;
};

class ConfigfsGadget {
 public:
  // Creates /sys/kernel/config/usb_gadget/<name> with one configuration. Throws with the path
  // that failed.
  ConfigfsGadget(std::string name, const GadgetIdentity& identity);
  ~ConfigfsGadget();
  ConfigfsGadget(const ConfigfsGadget&) = delete;
  ConfigfsGadget& operator=(const ConfigfsGadget&) = delete;

  // Creates functions/<type>.<instance> and links it into the configuration; returns its folder.
  // `prepare` runs on the folder before the link (UVC needs its descriptor tree by then).
  std::string add_function(const std::string& type, const std::string& instance,
                           const std::function<void(const std::string&)>& prepare = {});
  std::string root() const { return root_; }

  // Binds to the first UDC in /sys/class/udc (or BOLO_HIL_UDC), i.e. plugs the device in.
  void bind();
  void unbind();
  bool bound() const { return bound_; }

 private:
  std::string root_;
  std::vector<std::string> created_;  // removed in reverse order
  std::vector<std::string> links_;
  bool bound_ = false;
};

// Writes `value` to a configfs/sysfs attribute; throws naming the file.
void write_attribute(const std::string& path, const std::string& value);
void make_dir(const std::string& path);
// A configfs symbolic link `link` -> `target`; throws naming the link.
void make_link(const std::string& target, const std::string& link);

}  // namespace bolo::hil
