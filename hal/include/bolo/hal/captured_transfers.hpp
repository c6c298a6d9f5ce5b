#pragma once
// A captured bulk-transfer log replayed as a BulkInTransport: the same source code that runs on
// libusb runs on it. The log format is the shared capture's (../shared/data/usb/flirone-pro/):
// a folder of N.txt files numbered from 1 in capture order, each one transfer as hex text (empty
// file = zero-length transfer). Host code: throws std::runtime_error naming the file and offset.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "bolo/hal/usb_transport.hpp"

namespace bolo::hal {

class CapturedTransfers final : public BulkInTransport {
 public:
  explicit CapturedTransfers(const std::filesystem::path& dir);
  explicit CapturedTransfers(std::vector<std::vector<std::uint8_t>> transfers)
      : transfers_(std::move(transfers)) {}

  Transfer next(std::span<std::uint8_t> buffer, std::uint32_t timeout_ms) override;
  bool reconnect(std::uint32_t) override { return false; }

  const std::vector<std::vector<std::uint8_t>>& transfers() const { return transfers_; }
  void rewind() { next_ = 0; }

 private:
  std::vector<std::vector<std::uint8_t>> transfers_;
  std::size_t next_ = 0;
};

// One transfer's hex text -> bytes (whitespace ignored); throws naming `file` and the offset.
std::vector<std::uint8_t> parse_hex_transfer(const std::string& text, const std::filesystem::path& file);

}  // namespace bolo::hal
