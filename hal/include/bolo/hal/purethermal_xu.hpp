#pragma once
// The Lepton command interface as a PureThermal board exposes it: one UVC extension unit per
// Lepton SDK module (AGC 3, OEM 4, RAD 5, SYS 6, VID 7; GUID "pt1-lep-<module>-0000"), one control
// per command: selector = ((command id & 0xff) >> 2) + 1. GET_CUR / SET_CUR carry the
// attribute's 16-bit words little endian; a run command is a 1-byte SET_CUR. Command ids from
// FLIR's Lepton Software IDD. Pure encoding: no I/O, no allocation, no exceptions (board-safe).
// The HIL emulator's extension units are declared from this table (docs/hil.md).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace bolo::hal {

// UVC class request codes (UVC 1.5, table A-8) as UVCIOC_CTRL_QUERY and the gadget carry them.
enum class UvcRequest : std::uint8_t { set_cur = 0x01, get_cur = 0x81, get_len = 0x85, get_info = 0x86 };

enum class LeptonValue : std::uint8_t {
  none,          // a run command: no attribute
  centikelvin,   // uint16, K x 100 -> decoded to milli-degrees Celsius
  enumeration,   // uint32 (two words, low word first)
};

struct LeptonXuCommand {
  const char* name;           // as errors and `bolo devices` name it
  std::uint16_t command_id;   // Lepton SDK command id (module base + offset, no type bits)
  LeptonValue value;
  bool settable;
};

// The commands bolo uses. Gain mode: 0 high, 1 low, 2 auto; enable states: 0 off, 1 on.
inline constexpr LeptonXuCommand kLeptonRunFfc{"SYS Run FFC", 0x0242, LeptonValue::none, true};
inline constexpr LeptonXuCommand kLeptonFpaTemperature{"SYS FPA temperature", 0x0214, LeptonValue::centikelvin, false};
inline constexpr LeptonXuCommand kLeptonHousingTemperature{"SYS AUX (housing) temperature", 0x0210,
                                                           LeptonValue::centikelvin, false};
inline constexpr LeptonXuCommand kLeptonGainMode{"SYS gain mode", 0x0248, LeptonValue::enumeration, true};
inline constexpr LeptonXuCommand kLeptonRadiometry{"RAD radiometry enable", 0x4E10, LeptonValue::enumeration, true};
inline constexpr LeptonXuCommand kLeptonAgc{"AGC enable", 0x0100, LeptonValue::enumeration, true};
inline constexpr std::array<LeptonXuCommand, 6> kLeptonXuCommands{kLeptonRunFfc, kLeptonFpaTemperature,
                                                                  kLeptonHousingTemperature, kLeptonGainMode,
                                                                  kLeptonRadiometry, kLeptonAgc};

// Extension unit of the command's module (0 for a module the firmware does not expose).
std::uint8_t purethermal_xu_unit(std::uint16_t command_id);
// The control selector of a command within its unit.
std::uint8_t purethermal_xu_selector(std::uint16_t command_id);
// Bytes GET_CUR / SET_CUR carry: 1 for a run command, else 2 per attribute word.
std::size_t purethermal_xu_length(const LeptonXuCommand& command);

// A request's data: the 1-byte run payload, or `value` in the attribute's words. Returns the
// length written; 0 when `out` is too small or the command takes no such value.
std::size_t encode_purethermal_set(const LeptonXuCommand& command, std::uint32_t value, std::span<std::uint8_t> out);
// A GET_CUR reply: centikelvin -> milli-degrees Celsius, an enumeration as is; nothing for a
// reply of the wrong length, a run command, or a temperature of 0 (no reading).
std::optional<std::int32_t> decode_purethermal_reply(const LeptonXuCommand& command,
                                                     std::span<const std::uint8_t> reply);

// The 16-byte GUID of a module's unit ("pt1-lep-sys-0000" for unit 6); nothing for another unit.
std::optional<std::array<std::uint8_t, 16>> purethermal_xu_guid(std::uint8_t unit);
// True when a USB configuration descriptor set (as sysfs `descriptors` holds it) has a UVC
// extension unit 6 with the PureThermal SYS GUID, i.e. a board that runs Lepton SYS commands.
bool has_purethermal_sys_unit(std::span<const std::uint8_t> descriptors);

}  // namespace bolo::hal
