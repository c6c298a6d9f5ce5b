#include "bolo/hal/purethermal_xu.hpp"

#include <algorithm>

#include "bolo/hal/lepton_telemetry.hpp"

namespace bolo::hal {
namespace {

struct Module {
  std::uint8_t base;  // command id bits 8-11
  std::uint8_t unit;
  char name[4];
};
// The PureThermal firmware's unit per Lepton SDK module (RAD's ids also carry the OEM bit 0x4000).
constexpr std::array<Module, 5> kModules{{{0x1, 3, "agc"}, {0x8, 4, "oem"}, {0xE, 5, "rad"}, {0x2, 6, "sys"},
                                          {0x3, 7, "vid"}}};

constexpr std::uint8_t kCsInterface = 0x24;
constexpr std::uint8_t kVcExtensionUnit = 0x06;
constexpr std::uint8_t kSysUnit = 6;

}  // namespace

std::uint8_t purethermal_xu_unit(std::uint16_t command_id) {
  const auto base = static_cast<std::uint8_t>((command_id >> 8) & 0x0F);
  for (const Module& m : kModules)
    if (m.base == base) return m.unit;
  return 0;
}

std::uint8_t purethermal_xu_selector(std::uint16_t command_id) {
  return static_cast<std::uint8_t>(((command_id & 0xFF) >> 2) + 1);
}

std::size_t purethermal_xu_length(const LeptonXuCommand& command) {
  switch (command.value) {
    case LeptonValue::none: return 1;
    case LeptonValue::centikelvin: return 2;
    case LeptonValue::enumeration: return 4;
  }
  return 0;
}

std::size_t encode_purethermal_set(const LeptonXuCommand& command, std::uint32_t value, std::span<std::uint8_t> out) {
  const std::size_t length = purethermal_xu_length(command);
  if (!command.settable || out.size() < length) return 0;
  if (command.value == LeptonValue::none) {
    out[0] = 0;
    return 1;
  }
  for (std::size_t i = 0; i < length; ++i) out[i] = static_cast<std::uint8_t>(value >> (8 * i));
  return length;
}

std::optional<std::int32_t> decode_purethermal_reply(const LeptonXuCommand& command,
                                                     std::span<const std::uint8_t> reply) {
  if (command.value == LeptonValue::none || reply.size() != purethermal_xu_length(command)) return std::nullopt;
  std::uint32_t raw = 0;
  for (std::size_t i = 0; i < reply.size(); ++i) raw |= std::uint32_t{reply[i]} << (8 * i);
  if (command.value == LeptonValue::enumeration) return static_cast<std::int32_t>(raw);
  if (raw == 0) return std::nullopt;
  return centikelvin_to_mc(static_cast<std::uint16_t>(raw));
}

std::optional<std::array<std::uint8_t, 16>> purethermal_xu_guid(std::uint8_t unit) {
  for (const Module& m : kModules) {
    if (m.unit != unit) continue;
    std::array<std::uint8_t, 16> guid{'p', 't', '1', '-', 'l', 'e', 'p', '-', 0, 0, 0, '-', '0', '0', '0', '0'};
    for (std::size_t i = 0; i < 3; ++i) guid[8 + i] = static_cast<std::uint8_t>(m.name[i]);
    return guid;
  }
  return std::nullopt;
}

bool has_purethermal_sys_unit(std::span<const std::uint8_t> descriptors) {
  const auto guid = purethermal_xu_guid(kSysUnit);
  // Extension unit descriptor: bLength, 0x24, 0x06, bUnitID, guidExtensionCode[16], ...
  for (std::size_t at = 0; at + 2 <= descriptors.size();) {
    const std::uint8_t length = descriptors[at];
    if (length < 2 || at + length > descriptors.size()) return false;
    if (length >= 20 && descriptors[at + 1] == kCsInterface && descriptors[at + 2] == kVcExtensionUnit &&
        descriptors[at + 3] == kSysUnit) {
      const std::span<const std::uint8_t> code = descriptors.subspan(at + 4, guid->size());
      if (std::equal(guid->begin(), guid->end(), code.begin())) return true;
    }
    at += length;
  }
  return false;
}

}  // namespace bolo::hal
