#pragma once
// A UVC extension unit that logs every request and answers GET_CUR from a table (tests).

#include <cerrno>
#include <cstdint>
#include <map>
#include <initializer_list>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bolo/hal/uvc_controls.hpp"

namespace bolo::test {

class FakeUvcXu final : public hal::UvcExtensionUnit {
 public:
  struct Request {
    std::uint8_t unit, selector;
    hal::UvcRequest request;
    std::vector<std::uint8_t> data;  // as sent (SET_CUR) or as answered
  };
  int query(std::uint8_t unit, std::uint8_t selector, hal::UvcRequest request, std::span<std::uint8_t> data) override {
    if (request == hal::UvcRequest::get_cur) {
      const auto it = replies.find({unit, selector});
      if (it == replies.end() || it->second.size() != data.size()) return EPIPE;  // the firmware stalls
      std::copy(it->second.begin(), it->second.end(), data.begin());
    }
    log.push_back({unit, selector, request, {data.begin(), data.end()}});
    return refuse;
  }
  std::map<std::pair<std::uint8_t, std::uint8_t>, std::vector<std::uint8_t>> replies;  // GET_CUR by unit, selector
  int refuse = 0;  // the errno every request fails with; 0 = none
  std::vector<Request> log;
};

// A USB descriptor set as sysfs `descriptors` holds it: device, configuration, the video control
// interface's header, then one extension unit (bUnitID `unit`, guidExtensionCode `guid`).
inline std::vector<std::uint8_t> descriptors_with_extension_unit(std::uint8_t unit, const std::string& guid) {
  std::vector<std::uint8_t> d;
  const auto append = [&d](std::initializer_list<int> bytes) {
    for (int b : bytes) d.push_back(static_cast<std::uint8_t>(b));
  };
  append({18, 0x01, 0, 2, 0xEF, 2, 1, 64, 0x4E, 0x1E, 0, 1, 0, 2, 1, 2, 3, 1});  // device
  append({9, 0x02, 0, 0, 2, 1, 0, 0x80, 50});                                   // configuration
  append({9, 0x04, 0, 0, 1, 0x0E, 0x01, 0, 0});                                 // interface: video control
  append({13, 0x24, 0x01, 0x10, 0x01, 0, 0, 0, 0, 0, 0, 1, 1});                 // VC header
  // Extension unit: bLength 26, CS_INTERFACE, VC_EXTENSION_UNIT, bUnitID, guidExtensionCode,
  // bNumControls, bNrInPins, baSourceID, bControlSize, bmControls (2), iExtension.
  append({26, 0x24, 0x06, unit});
  for (char c : guid) d.push_back(static_cast<std::uint8_t>(c));
  append({24, 1, 2, 2, 0xFF, 0xFF, 0});
  return d;
}

}  // namespace bolo::test
