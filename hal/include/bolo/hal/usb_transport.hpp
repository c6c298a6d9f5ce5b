#pragma once
// The seam between the USB protocol sources and the wire: a source asks for the next completed
// bulk IN transfer and gets its bytes. On a device it is libusb (usb_libusb.hpp); in tests and
// replays it is a captured transfer log (captured_transfers.hpp). Board-safe interface.

#include <cstdint>
#include <span>

namespace bolo::hal {

enum class TransferStatus : std::uint8_t {
  ok,            // `bytes` bytes arrived (0 is a valid zero-length transfer)
  timeout,       // nothing within the timeout
  error,         // the transfer failed (stall, overflow, I/O error): data lost
  disconnected,  // the device is gone
  end,           // a replayed log is exhausted: nothing more will come
};

struct Transfer {
  TransferStatus status = TransferStatus::ok;
  std::size_t bytes = 0;
  std::int64_t arrival_ns = 0;  // host monotonic clock; 0 when unknown (replays)
};

class BulkInTransport {
 public:
  virtual ~BulkInTransport() = default;
  // Waits up to `timeout_ms` for the next completed bulk IN transfer and copies it into `buffer`
  // (a longer transfer is cut and reported as `error`).
  virtual Transfer next(std::span<std::uint8_t> buffer, std::uint32_t timeout_ms) = 0;
  // After `disconnected`: waits up to `timeout_ms` for the device to come back and streams again.
  virtual bool reconnect(std::uint32_t timeout_ms) = 0;
};

// Request/response devices (Seek): vendor control requests (type vendor, wValue 0, wIndex 0) as
// well as bulk reads. `bytes` of the result is what was transferred.
class VendorUsbTransport : public BulkInTransport {
 public:
  virtual Transfer control_out(std::uint8_t request, std::span<const std::uint8_t> data) = 0;
  virtual Transfer control_in(std::uint8_t request, std::span<std::uint8_t> data) = 0;
};

}  // namespace bolo::hal
