#include "bolo/hal/captured_transfers.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace bolo::hal {
namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::vector<std::uint8_t> parse_hex_transfer(const std::string& text, const std::filesystem::path& file) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(text.size() / 2);
  int high = -1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    const int d = hex_digit(c);
    if (d < 0) {
      std::ostringstream m;
      m << file.string() << ": offset " << i << ": not a hex digit (transfer logs are hex text)";
      throw std::runtime_error(m.str());
    }
    if (high < 0) {
      high = d;
    } else {
      bytes.push_back(static_cast<std::uint8_t>(high << 4 | d));
      high = -1;
    }
  }
  if (high >= 0) throw std::runtime_error(file.string() + ": odd number of hex digits");
  return bytes;
}

CapturedTransfers::CapturedTransfers(const std::filesystem::path& dir) {
  std::vector<std::pair<unsigned long, std::filesystem::path>> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string stem = entry.path().stem().string();
    if (entry.path().extension() != ".txt" || stem.empty() ||
        !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    files.emplace_back(std::stoul(stem), entry.path());
  }
  if (ec) throw std::runtime_error(dir.string() + ": cannot read the transfer log: " + ec.message());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw std::runtime_error(dir.string() + ": no transfer files (1.txt, 2.txt, ...)");
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (files[i].first != i + 1)
      throw std::runtime_error(dir.string() + ": transfer " + std::to_string(i + 1) +
                               ".txt missing (the log must be numbered 1..N without gaps)");
    std::ifstream in(files[i].second, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) throw std::runtime_error(files[i].second.string() + ": cannot read");
    transfers_.push_back(parse_hex_transfer(text.str(), files[i].second));
  }
}

Transfer CapturedTransfers::next(std::span<std::uint8_t> buffer, std::uint32_t) {
  Transfer t;
  if (next_ >= transfers_.size()) {
    t.status = TransferStatus::end;
    return t;
  }
  const std::vector<std::uint8_t>& bytes = transfers_[next_++];
  if (bytes.size() > buffer.size()) {
    t.status = TransferStatus::error;  // libusb would report an overflow
    return t;
  }
  if (!bytes.empty()) std::memcpy(buffer.data(), bytes.data(), bytes.size());
  t.bytes = bytes.size();
  return t;
}

}  // namespace bolo::hal
