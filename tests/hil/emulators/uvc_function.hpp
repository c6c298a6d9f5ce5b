#pragma once
// The configfs tree of a UVC gadget function (usb_f_uvc) laid out as the PureThermal: control
// header, one uncompressed Y16 format with the 160x120 and 160x122 frames (uvc_control.hpp),
// streaming header linked for full, high and super speed.

#include <string>

namespace bolo::hil::uvc {

// Fills functions/uvc.<instance> (`function`) before it is linked into the configuration.
// Throws naming the attribute or link that failed.
void describe_purethermal(const std::string& function);

// The gadget's V4L2 output node (/dev/videoN) of the bound UVC function whose configfs folder is
// named `function_name` (uvc.<instance>); empty while it is not registered.
std::string find_gadget_node(const std::string& function_name);

// The streaming payload size the loaded usb_f_uvc uses (its bulk_payload parameter). Throws
// when the module has none: Debian's isochronous-only module is loaded instead of the bulk one
// (toolchain/vm/uvc-gadget.sh).
unsigned read_bulk_payload();

}  // namespace bolo::hil::uvc
