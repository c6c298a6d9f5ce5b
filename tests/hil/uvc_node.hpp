#pragma once
// The emulated PureThermal's capture node as the host's uvcvideo made it: the first uvcvideo node
// offering Y16, waited for up to 20 s (the gadget binds and enumerates after the program starts).

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include "bolo/hal/v4l2_source.hpp"

namespace bolo::hil {

inline std::string find_uvc_node() {
  const auto patience = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  for (;;) {
    for (const hal::V4l2DeviceEntry& e : hal::list_v4l2_devices())
      if (e.driver == "uvcvideo" && !e.sizes(hal::V4l2Pixels::y16).empty()) return e.path;
    if (std::chrono::steady_clock::now() > patience) throw std::runtime_error("no uvcvideo Y16 node after 20 s");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace bolo::hil
