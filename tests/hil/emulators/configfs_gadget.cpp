#include "configfs_gadget.hpp"
#include "udc.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace bolo::hil {

namespace {

std::string hex4(std::uint16_t v) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%04x", v);
  return text;
}

}  // namespace

void write_attribute(const std::string& path, const std::string& value) {
  const int fd = ::open(path.c_str(), O_WRONLY);
  if (fd < 0) throw std::runtime_error(path + ": " + std::strerror(errno));
  // configfs attributes take the whole value in one write; an empty value still needs a byte.
  const std::string text = value.empty() ? std::string("\n") : value;
  const ssize_t n = ::write(fd, text.data(), text.size());
  const int saved = errno;
  ::close(fd);
  if (n < 0) throw std::runtime_error(path + ": writing '" + value + "': " + std::strerror(saved));
}

void make_dir(const std::string& path) {
  if (::mkdir(path.c_str(), 0755) != 0 && errno != EEXIST)
    throw std::runtime_error(path + ": " + std::strerror(errno));
}

ConfigfsGadget::ConfigfsGadget(std::string name, const GadgetIdentity& identity)
    : root_("/sys/kernel/config/usb_gadget/" + std::move(name)) {
  make_dir(root_);
  created_.push_back(root_);
  write_attribute(root_ + "/idVendor", hex4(identity.vendor_id));
  write_attribute(root_ + "/idProduct", hex4(identity.product_id));
  write_attribute(root_ + "/bcdDevice", hex4(identity.bcd_device));
  write_attribute(root_ + "/bcdUSB", "0x0200");
  write_attribute(root_ + "/bDeviceClass", std::to_string(identity.device_class));
  write_attribute(root_ + "/bDeviceSubClass", std::to_string(identity.device_subclass));
  write_attribute(root_ + "/bDeviceProtocol", std::to_string(identity.device_protocol));
  const std::string strings = root_ + "/strings/0x409";
  make_dir(strings);
  created_.push_back(strings);
  write_attribute(strings + "/manufacturer", identity.manufacturer);
  write_attribute(strings + "/product", identity.product);
  write_attribute(strings + "/serialnumber", identity.serial);
  const std::string config = root_ + "/configs/c.1";
  make_dir(config);
  created_.push_back(config);
  write_attribute(config + "/MaxPower", "500");
}

void make_link(const std::string& target, const std::string& link) {
  if (::symlink(target.c_str(), link.c_str()) != 0 && errno != EEXIST)
    throw std::runtime_error(link + " -> " + target + ": " + std::strerror(errno));
}

std::string ConfigfsGadget::add_function(const std::string& type, const std::string& instance,
                                         const std::function<void(const std::string&)>& prepare) {
  const std::string function = root_ + "/functions/" + type + "." + instance;
  make_dir(function);
  created_.push_back(function);
  if (prepare) prepare(function);
  const std::string link = root_ + "/configs/c.1/" + type + "." + instance;
  make_link(function, link);
  links_.push_back(link);
  return function;
}

void ConfigfsGadget::bind() {
  write_attribute(root_ + "/UDC", first_udc());
  bound_ = true;
}

void ConfigfsGadget::unbind() {
  write_attribute(root_ + "/UDC", "");
  bound_ = false;
}

ConfigfsGadget::~ConfigfsGadget() {
  try {
    if (bound_) unbind();
  } catch (const std::exception&) {
    // Tear-down is best effort: the VM powers off after the scenario anyway.
  }
  for (auto it = links_.rbegin(); it != links_.rend(); ++it) ::unlink(it->c_str());
  for (auto it = created_.rbegin(); it != created_.rend(); ++it) ::rmdir(it->c_str());
}

}  // namespace bolo::hil
