#pragma once
// The Seek's vendor requests and the start-up sequence the public driver (libseek-thermal) sends,
// per model (usb-thermal-cores.md, "Seek Thermal"). The one definition of what SeekSource sends;
// the test device and the HIL emulator check it against their own, separately written, lists.
// Protocol layer: no I/O, no allocation.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "bolo/hal/seek_frame_parser.hpp"

namespace bolo::hal {

namespace seek {
// Vendor request codes (usb-thermal-cores.md).
enum Request : std::uint8_t {
  kGetErrorCode = 53,
  kReadChipId = 54,
  kToggleShutter = 55,
  kSetOperationMode = 60,
  kGetOperationMode = 61,
  kSetImageProcessingMode = 62,
  kGetFirmwareInfo = 78,
  kStartGetImageTransfer = 83,
  kTargetPlatform = 84,
  kSetFirmwareInfoFeatures = 85,
  kSetFactorySettingsFeatures = 86,
  kGetFactorySettings = 88,
  kResetDevice = 89,
};
}  // namespace seek

// One control request: OUT with `length` payload bytes, or IN reading `length` bytes.
struct SeekControlStep {
  bool read = false;
  std::uint8_t request = 0;
  std::uint8_t length = 0;
  std::array<std::uint8_t, 6> payload{};  // OUT only
  std::span<const std::uint8_t> data() const { return {payload.data(), read ? 0u : length}; }
};

// The CompactPro's is the longest: 12 + 80 factory-settings pairs + 4 steps.
inline constexpr std::size_t kSeekMaxStartupSteps = 176;

// Step 0 is TARGET_PLATFORM [01]; if it fails the driver sends the close sequence and step 0
// once more, then the rest in order, stopping at the first failure.
class SeekStartupSequence {
 public:
  explicit SeekStartupSequence(const SeekModel& model);
  std::span<const SeekControlStep> steps() const { return {steps_.data(), size_}; }

 private:
  void out(std::uint8_t request, std::initializer_list<std::uint8_t> payload);
  void in(std::uint8_t request, std::uint8_t length);
  std::array<SeekControlStep, kSeekMaxStartupSteps> steps_{};
  std::size_t size_ = 0;
};

// Close: SET_OPERATION_MODE [00 00], sent this many times (as the driver does).
inline constexpr int kSeekCloseRepeats = 3;
inline constexpr std::array<std::uint8_t, 2> kSeekIdleMode{0, 0};

// Open: after the sequence the first frame must be the start-up frame (type 4); a failed frame
// request runs the whole sequence again, up to this many attempts in all.
inline constexpr int kSeekStartAttempts = 3;

}  // namespace bolo::hal
