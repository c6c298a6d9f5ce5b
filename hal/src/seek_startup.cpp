#include "bolo/hal/seek_startup.hpp"

namespace bolo::hal {

void SeekStartupSequence::out(std::uint8_t request, std::initializer_list<std::uint8_t> payload) {
  SeekControlStep& s = steps_[size_++];
  s.request = request;
  s.length = static_cast<std::uint8_t>(payload.size());
  std::size_t i = 0;
  for (std::uint8_t b : payload) s.payload[i++] = b;
}

void SeekStartupSequence::in(std::uint8_t request, std::uint8_t length) {
  SeekControlStep& s = steps_[size_++];
  s.read = true;
  s.request = request;
  s.length = length;
}

SeekStartupSequence::SeekStartupSequence(const SeekModel& model) {
  using namespace seek;
  out(kTargetPlatform, {0x01});
  out(kSetOperationMode, {0x00, 0x00});
  in(kGetFirmwareInfo, 4);
  in(kReadChipId, 12);
  if (model.family == SeekFamily::compact) {
    out(kSetFactorySettingsFeatures, {0x20, 0x00, 0x30, 0x00, 0x00, 0x00});
    in(kGetFactorySettings, 64);
    out(kSetFactorySettingsFeatures, {0x20, 0x00, 0x50, 0x00, 0x00, 0x00});
    in(kGetFactorySettings, 64);
    out(kSetFactorySettingsFeatures, {0x0c, 0x00, 0x70, 0x00, 0x00, 0x00});
    in(kGetFactorySettings, 24);
    out(kSetFactorySettingsFeatures, {0x06, 0x00, 0x08, 0x00, 0x00, 0x00});
    in(kGetFactorySettings, 12);
    out(kSetImageProcessingMode, {0x08, 0x00});
    in(kGetOperationMode, 2);
    out(kSetImageProcessingMode, {0x08, 0x00});
    out(kSetOperationMode, {0x01, 0x00});
    in(kGetOperationMode, 2);
    return;
  }
  out(kSetFactorySettingsFeatures, {0x06, 0x00, 0x08, 0x00, 0x00, 0x00});
  in(kGetFactorySettings, 12);
  out(kSetFirmwareInfoFeatures, {0x17, 0x00});
  in(kGetFirmwareInfo, 64);
  out(kSetFactorySettingsFeatures, {0x01, 0x00, 0x00, 0x06, 0x00, 0x00});
  in(kGetFactorySettings, 2);
  out(kSetFactorySettingsFeatures, {0x01, 0x00, 0x01, 0x06, 0x00, 0x00});
  in(kGetFactorySettings, 2);
  for (unsigned address = 0; address <= 2528; address += 32) {
    out(kSetFactorySettingsFeatures, {0x20, 0x00, static_cast<std::uint8_t>(address & 0xFF),
                                      static_cast<std::uint8_t>(address >> 8), 0x00, 0x00});
    in(kGetFactorySettings, 64);
  }
  out(kSetFirmwareInfoFeatures, {0x15, 0x00});
  in(kGetFirmwareInfo, 64);
  out(kSetImageProcessingMode, {0x08, 0x00});
  out(kSetOperationMode, {0x01, 0x00});
}

}  // namespace bolo::hal
