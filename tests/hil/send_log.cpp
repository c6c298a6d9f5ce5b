#include "send_log.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace bolo::hil {

Expectation read_send_log(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the emulator's send log");
  Expectation e;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string refused = "# refused-requests ";
    if (line.rfind(refused, 0) == 0) e.refused_requests = std::stol(line.substr(refused.size()));
    if (!line.empty() && line[0] == '#') continue;  // frames the host consumes without delivering
    if (line == "lost-by-emulator") {
      ++e.lost_by_emulator;
      continue;
    }
    std::istringstream fields(line);
    std::string tag, fault, hash, image;
    SentFrame f;
    std::size_t size = 0;
    if (!(fields >> tag >> f.index >> fault >> hash >> f.counter >> size >> image) || tag != "frame")
      throw std::runtime_error(path + ":" + std::to_string(number) + ": malformed send-log line");
    f.fault = parse_fault(fault);
    f.hash = std::stoull(hash, nullptr, 16);
    f.image_hash = std::stoull(image, nullptr, 16);
    ++e.frames_sent;
    ++e.injected[static_cast<std::size_t>(f.fault)];
    if (!fault_loses_frame(f.fault)) e.deliver.push_back(f);
    if (f.fault == Fault::duplicate) e.deliver.push_back(f);
  }
  return e;
}

bool counter_surprise(std::uint32_t previous, std::uint32_t next) {
  const auto step = static_cast<std::int32_t>(next - previous);
  return step < 0 || step > 64;
}

}  // namespace bolo::hil
