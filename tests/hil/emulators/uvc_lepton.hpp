#pragma once
// The emulated PureThermal's Lepton command interface: class requests to its VideoControl
// interface answered as the board's firmware does. The extension units (AGC 3, RAD 5, SYS 6; their
// descriptors are the patched usb_f_uvc's, toolchain/vm/uvc-gadget-purethermal-xu.patch) carry one
// control per Lepton command bolo uses (hal/purethermal_xu.hpp): temperatures to read, gain mode /
// radiometry / AGC enable stored and read back, SYS Run FFC handed to the frame feed. Entity 0
// answers the request error code control (UVC 1.1, 4.2.1.2) uvcvideo reads after a stall.
// Pure: no I/O.

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bolo/hal/purethermal_xu.hpp"

namespace bolo::hil::uvc {

// VC_REQUEST_ERROR_CODE_CONTROL values (UVC 1.1, table 4-7) the emulator uses.
enum class RequestError : std::uint8_t {
  none = 0, out_of_range = 4, invalid_unit = 5, invalid_control = 6, invalid_request = 7,
};

class LeptonXu {
 public:
  // Temperatures in centikelvin, as the telemetry rows carry them. `refuse`: every extension-unit
  // request is stalled (a board whose firmware does not answer).
  LeptonXu(std::uint16_t fpa_temp_ck, std::uint16_t housing_temp_ck, bool refuse = false);

  // An IN request (GET_*) to `unit` (0: the interface itself): the reply (wLength bytes at most),
  // or nothing to stall.
  std::optional<std::vector<std::uint8_t>> get(std::uint8_t request, std::uint8_t unit, std::uint8_t selector,
                                               std::uint16_t length);
  // SET_CUR's setup stage: whether its data stage is taken (else stall).
  bool accepts_set(std::uint8_t request, std::uint8_t unit, std::uint8_t selector, std::uint16_t length);
  // SET_CUR's data stage (after accepts_set): stores the value; Run FFC becomes pending. A value out
  // of the control's range is ignored and counted refused (the status stage cannot stall here).
  void set(std::uint8_t unit, std::uint8_t selector, std::span<const std::uint8_t> data);

  // A Run FFC the stream has not shown yet; taking it clears it.
  bool take_ffc();
  std::uint64_t ffc_runs() const { return ffc_runs_; }
  // Requests to the extension units answered / refused (stalled or ignored); refusals of the
  // interface's other entities (uvcvideo asks the processing unit's standard controls) apart.
  std::uint64_t answered() const { return answered_; }
  std::uint64_t refused() const { return refused_; }
  std::uint64_t refused_other() const { return refused_other_; }
  // What the last request got, e.g. "GET_CUR SYS gain mode (unit 6, selector 19): 1".
  const std::string& last() const { return last_; }
  // Whether it was uvcvideo probing a standard control (or reading the error code after one).
  bool last_was_standard() const { return last_standard_; }

 private:
  const hal::LeptonXuCommand* command(std::uint8_t unit, std::uint8_t selector) const;
  std::uint32_t current(const hal::LeptonXuCommand& c) const;
  bool refuse(std::uint8_t unit, std::uint8_t selector, RequestError why, const char* request);

  std::uint16_t fpa_temp_ck_, housing_temp_ck_;
  bool refuse_all_;
  std::map<std::uint16_t, std::uint32_t> values_;  // command id -> stored enumeration
  bool ffc_pending_ = false;
  std::uint64_t ffc_runs_ = 0, answered_ = 0, refused_ = 0, refused_other_ = 0;
  RequestError error_ = RequestError::none;
  std::string last_;
  bool last_standard_ = false;
};

// The request's name as UVC 1.1 table A-8 spells it ("GET_CUR"), "request 0xNN" for another.
std::string request_name(std::uint8_t request);

}  // namespace bolo::hil::uvc
