#include "udc.hpp"

#include <dirent.h>

#include <cstdlib>
#include <stdexcept>

namespace bolo::hil {

std::string first_udc() {
  if (const char* forced = std::getenv("BOLO_HIL_UDC")) return forced;
  DIR* dir = opendir("/sys/class/udc");
  if (dir == nullptr) throw std::runtime_error("/sys/class/udc: no UDC (is dummy_hcd loaded?)");
  std::string name;
  while (const dirent* entry = readdir(dir)) {
    if (entry->d_name[0] != '.') {
      name = entry->d_name;
      break;
    }
  }
  closedir(dir);
  if (name.empty()) throw std::runtime_error("/sys/class/udc: empty (is dummy_hcd loaded?)");
  return name;
}

}  // namespace bolo::hil
