// The two text formats of bolo diagnose: diagnosis.json (read_diagnosis_json) and the simulator
// configuration simulate.cfg (parse_simulator_config), both fed the same input. Properties: a
// refusal is a std::runtime_error (never a crash or another exception type); an accepted
// diagnosis.json has inclusive frame ranges with first <= last; every accepted config entry has
// a non-empty option name and at least one value.

#include <cstdint>
#include <stdexcept>
#include <string>

#include "bolo/diagnose/diagnose.hpp"
#include "bolo/diagnose/simulator_config.hpp"
#include "fuzz_support.hpp"

using namespace bolo;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const diag::Diagnosis d = diag::read_diagnosis_json(text);
    for (const auto& f : d.findings) {
      BOLO_FUZZ_CHECK(!f.effect.empty());
      for (const auto& [a, b] : f.where.frames) BOLO_FUZZ_CHECK(a >= 0 && a <= b);
    }
    for (const auto& u : d.unexplained)
      for (const auto& [a, b] : u.where.frames) BOLO_FUZZ_CHECK(a >= 0 && a <= b);
  } catch (const std::runtime_error&) {
  }
  try {
    for (const auto& e : diag::parse_simulator_config(text, "fuzz.cfg")) {
      BOLO_FUZZ_CHECK(!e.option.empty());
      BOLO_FUZZ_CHECK(!e.values.empty());
      BOLO_FUZZ_CHECK(e.line >= 1);
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}
