#include "fault_plan.hpp"

#include <sstream>
#include <stdexcept>

namespace bolo::hil {

namespace {

constexpr Fault kAll[] = {Fault::short_transfer, Fault::corrupt,       Fault::stall,    Fault::timeout,
                          Fault::disconnect,     Fault::frame_id_jump, Fault::duplicate};

std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace

const char* fault_name(Fault fault) {
  switch (fault) {
    case Fault::none: return "none";
    case Fault::short_transfer: return "short_transfer";
    case Fault::corrupt: return "corrupt";
    case Fault::stall: return "stall";
    case Fault::timeout: return "timeout";
    case Fault::disconnect: return "disconnect";
    case Fault::frame_id_jump: return "frame_id_jump";
    case Fault::duplicate: return "duplicate";
  }
  return "?";
}

Fault parse_fault(const std::string& name) {
  if (name == "none") return Fault::none;
  for (Fault f : kAll)
    if (name == fault_name(f)) return f;
  throw std::runtime_error("unknown fault '" + name + "'");
}

bool fault_loses_frame(Fault fault) {
  switch (fault) {
    case Fault::short_transfer:
    case Fault::corrupt:
    case Fault::stall:
    case Fault::timeout:
    case Fault::disconnect: return true;
    default: return false;
  }
}

std::vector<Fault> parse_fault_list(const std::string& list) {
  if (list == "all") return {std::begin(kAll), std::end(kAll)};
  std::vector<Fault> faults;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ','))
    if (!name.empty()) faults.push_back(parse_fault(name));
  return faults;
}

FaultPlan::FaultPlan(double rate, std::uint64_t seed, std::vector<Fault> kinds)
    : threshold_(static_cast<std::uint64_t>(rate * 4294967296.0)), seed_(seed), kinds_(std::move(kinds)) {
  if (rate < 0 || rate > 1) throw std::runtime_error("fault rate must be within 0..1");
  if (kinds_.empty()) kinds_.assign(std::begin(kAll), std::end(kAll));
}

Fault FaultPlan::at(std::uint64_t frame) const {
  if (threshold_ == 0) return Fault::none;
  const std::uint64_t h = mix(seed_ ^ mix(frame));
  if ((h & 0xFFFFFFFFULL) >= threshold_) return Fault::none;
  // The kind comes from the hash bits the rate test did not use.
  const std::uint64_t nth = (h >> 32) % kinds_.size();
  return kinds_[nth];
}

}  // namespace bolo::hil
