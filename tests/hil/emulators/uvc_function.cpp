#include "uvc_function.hpp"

#include <dirent.h>

#include <fstream>
#include <stdexcept>

#include "configfs_gadget.hpp"
#include "uvc_control.hpp"

namespace bolo::hil::uvc {

void describe_purethermal(const std::string& f) {
  // Control: the header, linked for full/high speed ("fs") and super speed ("ss").
  make_dir(f + "/control/header/h");
  make_link(f + "/control/header/h", f + "/control/class/fs/h");
  make_link(f + "/control/header/h", f + "/control/class/ss/h");

  // Streaming: format and frames are written before anything links them (linked ones are busy).
  const std::string format = f + "/streaming/uncompressed/y16";
  make_dir(format);
  write_attribute(format + "/guidFormat", std::string(kGuidY16.begin(), kGuidY16.end()));
  write_attribute(format + "/bBitsPerPixel", "16");
  for (const FrameSize& size : kFrames) {
    const std::string frame = format + "/" + std::to_string(size.width) + "x" + std::to_string(size.height);
    make_dir(frame);
    write_attribute(frame + "/wWidth", std::to_string(size.width));
    write_attribute(frame + "/wHeight", std::to_string(size.height));
    write_attribute(frame + "/dwMaxVideoFrameBufferSize", std::to_string(size.bytes()));
    const std::uint64_t bits_per_second = std::uint64_t{size.bytes()} * 8 * 10'000'000 / kFrameInterval;
    write_attribute(frame + "/dwMinBitRate", std::to_string(bits_per_second));
    write_attribute(frame + "/dwMaxBitRate", std::to_string(bits_per_second));
    write_attribute(frame + "/dwDefaultFrameInterval", std::to_string(kFrameInterval));
    write_attribute(frame + "/dwFrameInterval", std::to_string(kFrameInterval));
  }
  make_dir(f + "/streaming/header/h");
  make_link(format, f + "/streaming/header/h/y16");
  for (const char* speed : {"fs", "hs", "ss"})
    make_link(f + "/streaming/header/h", f + "/streaming/class/" + speed + "/h");
}

std::string find_gadget_node(const std::string& function_name) {
  DIR* dir = opendir("/sys/class/video4linux");
  if (dir == nullptr) return {};
  std::string found;
  while (dirent* e = readdir(dir)) {
    if (e->d_name[0] == '.') continue;
    std::ifstream in(std::string("/sys/class/video4linux/") + e->d_name + "/function_name");
    std::string name;
    if (in >> name && name == function_name) {
      found = std::string("/dev/") + e->d_name;
      break;
    }
  }
  closedir(dir);
  return found;
}

unsigned read_bulk_payload() {
  const char* path = "/sys/module/usb_f_uvc/parameters/bulk_payload";
  std::ifstream in(path);
  unsigned payload = 0;
  if (!(in >> payload) || payload < 512)
    throw std::runtime_error(std::string(path) +
                             ": missing: the loaded usb_f_uvc streams isochronous only (Debian's); the HIL "
                             "VM needs the bulk build of toolchain/vm/uvc-gadget.sh");
  return payload;
}

}  // namespace bolo::hil::uvc
