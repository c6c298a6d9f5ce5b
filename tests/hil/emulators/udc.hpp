#pragma once
// The USB device controller a gadget binds to: BOLO_HIL_UDC, else the first in /sys/class/udc
// (dummy_hcd's in the VM). Throws std::runtime_error when there is none.

#include <string>

namespace bolo::hil {

std::string first_udc();

}  // namespace bolo::hil
