#include "uvc_lepton.hpp"

#include <cstdio>

#include "uvc_control.hpp"

namespace bolo::hil::uvc {

namespace {

// The VideoControl interface's own entities besides the extension units (the patched usb_f_uvc:
// camera terminal 1, processing unit 2, output terminal 8) and its request error code control.
constexpr std::uint8_t kCameraTerminal = 1, kProcessingUnit = 2, kOutputTerminal = 8;
constexpr std::uint8_t kRequestErrorCodeControl = 0x02;
// GET_INFO bits (UVC 1.1, 4.1.2): GET and SET supported.
constexpr std::uint8_t kInfoGet = 0x01, kInfoSet = 0x02;

// Factory defaults: gain mode high (0), radiometry on, AGC off.
constexpr std::uint32_t default_value(const hal::LeptonXuCommand& c) {
  return c.command_id == hal::kLeptonRadiometry.command_id ? 1 : 0;
}
// The largest value a settable enumeration takes: gain mode auto (2), else an enable state.
constexpr std::uint32_t maximum_value(const hal::LeptonXuCommand& c) {
  return c.command_id == hal::kLeptonGainMode.command_id ? 2 : 1;
}

std::vector<std::uint8_t> little_endian(std::uint32_t value, std::size_t bytes, std::uint16_t length) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
  if (out.size() > length) out.resize(length);
  return out;
}

bool standard_entity(std::uint8_t unit) {
  return unit == 0 || unit == kCameraTerminal || unit == kProcessingUnit || unit == kOutputTerminal;
}

// A refused request to an entity the interface has is an invalid control; to another, an invalid unit.
RequestError entity_error(std::uint8_t unit) {
  return standard_entity(unit) || hal::purethermal_xu_guid(unit) ? RequestError::invalid_control
                                                                 : RequestError::invalid_unit;
}

std::string where(std::uint8_t unit, std::uint8_t selector) {
  return "(unit " + std::to_string(unit) + ", selector " + std::to_string(selector) + ")";
}

}  // namespace

std::string request_name(std::uint8_t request) {
  switch (request) {
    case kSetCur: return "SET_CUR";
    case kGetCur: return "GET_CUR";
    case kGetMin: return "GET_MIN";
    case kGetMax: return "GET_MAX";
    case kGetRes: return "GET_RES";
    case kGetLen: return "GET_LEN";
    case kGetInfo: return "GET_INFO";
    case kGetDef: return "GET_DEF";
    default: {
      char text[24];
      std::snprintf(text, sizeof text, "request 0x%02x", request);
      return text;
    }
  }
}

LeptonXu::LeptonXu(std::uint16_t fpa_temp_ck, std::uint16_t housing_temp_ck, bool refuse)
    : fpa_temp_ck_(fpa_temp_ck), housing_temp_ck_(housing_temp_ck), refuse_all_(refuse) {
  for (const hal::LeptonXuCommand& c : hal::kLeptonXuCommands)
    if (c.value == hal::LeptonValue::enumeration) values_[c.command_id] = default_value(c);
}

const hal::LeptonXuCommand* LeptonXu::command(std::uint8_t unit, std::uint8_t selector) const {
  for (const hal::LeptonXuCommand& c : hal::kLeptonXuCommands)
    if (hal::purethermal_xu_unit(c.command_id) == unit && hal::purethermal_xu_selector(c.command_id) == selector)
      return &c;
  return nullptr;
}

std::uint32_t LeptonXu::current(const hal::LeptonXuCommand& c) const {
  if (c.value == hal::LeptonValue::enumeration) return values_.at(c.command_id);
  if (c.value == hal::LeptonValue::none) return 0;
  return c.command_id == hal::kLeptonFpaTemperature.command_id ? fpa_temp_ck_ : housing_temp_ck_;
}

bool LeptonXu::refuse(std::uint8_t unit, std::uint8_t selector, RequestError why, const char* request) {
  error_ = why;
  last_standard_ = standard_entity(unit);
  ++(last_standard_ ? refused_other_ : refused_);
  last_ = std::string(request) + " " + where(unit, selector) + ": refused (error code " +
          std::to_string(static_cast<int>(why)) + ")";
  return false;
}

std::optional<std::vector<std::uint8_t>> LeptonXu::get(std::uint8_t request, std::uint8_t unit,
                                                       std::uint8_t selector, std::uint16_t length) {
  const std::string name = request_name(request);
  if (unit == 0 && selector == kRequestErrorCodeControl && (request == kGetCur || request == kGetInfo)) {
    // Reading the code leaves it as it is (the next request sets it), and who it concerned.
    last_ = name + " request error code: " + std::to_string(static_cast<int>(error_));
    return little_endian(request == kGetCur ? static_cast<std::uint8_t>(error_) : kInfoGet, 1, length);
  }
  if (!hal::purethermal_xu_guid(unit) || refuse_all_) {
    refuse(unit, selector, entity_error(unit), name.c_str());
    return std::nullopt;
  }
  const hal::LeptonXuCommand* c = command(unit, selector);
  if (c == nullptr) {
    refuse(unit, selector, RequestError::invalid_control, name.c_str());
    return std::nullopt;
  }
  const std::size_t size = hal::purethermal_xu_length(*c);
  std::uint32_t value = 0;
  switch (request) {
    case kGetLen: value = static_cast<std::uint32_t>(size); break;
    case kGetInfo: value = (c->value == hal::LeptonValue::none ? 0 : kInfoGet) | (c->settable ? kInfoSet : 0); break;
    case kGetCur:
      if (c->value == hal::LeptonValue::none) {  // a run command has nothing to read
        refuse(unit, selector, RequestError::invalid_request, name.c_str());
        return std::nullopt;
      }
      value = current(*c);
      break;
    case kGetMin: value = 0; break;
    case kGetMax:
      value = c->value == hal::LeptonValue::enumeration ? maximum_value(*c)
              : c->value == hal::LeptonValue::centikelvin ? 0xFFFF : 0;
      break;
    case kGetRes: value = c->value == hal::LeptonValue::none ? 0 : 1; break;
    case kGetDef: value = c->value == hal::LeptonValue::enumeration ? default_value(*c) : current(*c); break;
    default:
      refuse(unit, selector, RequestError::invalid_request, name.c_str());
      return std::nullopt;
  }
  error_ = RequestError::none;
  last_standard_ = false;
  ++answered_;
  last_ = name + " " + c->name + " " + where(unit, selector) + ": " + std::to_string(value);
  return little_endian(value, request == kGetLen ? 2 : request == kGetInfo ? 1 : size, length);
}

bool LeptonXu::accepts_set(std::uint8_t request, std::uint8_t unit, std::uint8_t selector, std::uint16_t length) {
  const std::string name = request_name(request);
  if (!hal::purethermal_xu_guid(unit) || refuse_all_) return refuse(unit, selector, entity_error(unit), name.c_str());
  const hal::LeptonXuCommand* c = command(unit, selector);
  if (c == nullptr) return refuse(unit, selector, RequestError::invalid_control, name.c_str());
  if (request != kSetCur || !c->settable || length != hal::purethermal_xu_length(*c))
    return refuse(unit, selector, RequestError::invalid_request, name.c_str());
  return true;
}

void LeptonXu::set(std::uint8_t unit, std::uint8_t selector, std::span<const std::uint8_t> data) {
  const hal::LeptonXuCommand* c = command(unit, selector);
  if (c == nullptr || data.size() != hal::purethermal_xu_length(*c)) {
    refuse(unit, selector, RequestError::invalid_request, "SET_CUR");
    return;
  }
  if (c->value == hal::LeptonValue::none) {  // Run FFC: whatever the byte says
    ffc_pending_ = true;
    ++ffc_runs_;
  } else {
    std::uint32_t value = 0;
    for (std::size_t i = 0; i < data.size(); ++i) value |= std::uint32_t{data[i]} << (8 * i);
    if (value > maximum_value(*c)) {
      refuse(unit, selector, RequestError::out_of_range, "SET_CUR");
      return;
    }
    values_[c->command_id] = value;
  }
  error_ = RequestError::none;
  last_standard_ = false;
  ++answered_;
  last_ = std::string("SET_CUR ") + c->name + " " + where(unit, selector) + ": " +
          (c->value == hal::LeptonValue::none ? std::string("run") : std::to_string(values_[c->command_id]));
}

bool LeptonXu::take_ffc() {
  const bool pending = ffc_pending_;
  ffc_pending_ = false;
  return pending;
}

}  // namespace bolo::hil::uvc
