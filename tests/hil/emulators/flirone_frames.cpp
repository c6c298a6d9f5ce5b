#include "flirone_frames.hpp"
#include "fnv1a.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace bolo::hil::flirone {

namespace {

std::uint32_t le32(std::span<const std::uint8_t> b, std::size_t at) {
  return static_cast<std::uint32_t>(b[at]) | static_cast<std::uint32_t>(b[at + 1]) << 8 |
         static_cast<std::uint32_t>(b[at + 2]) << 16 | static_cast<std::uint32_t>(b[at + 3]) << 24;
}

void put_le32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

std::uint16_t le16(std::span<const std::uint8_t> b, std::size_t at) {
  return static_cast<std::uint16_t>(b[at] | b[at + 1] << 8);
}

void put_le16(Bytes& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v);
  b[at + 1] = static_cast<std::uint8_t>(v >> 8);
}

constexpr std::size_t kCounterAt = kHeaderBytes + 60 * kPacketBytes + 4 + 20 * 2;

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

Bytes parse_hex_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  Bytes out;
  out.reserve(s.size() / 2);
  int high = -1;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    const int v = hex_value(c);
    if (v < 0) throw std::runtime_error(path.string() + ": offset " + std::to_string(i) + ": not hex");
    if (high < 0) {
      high = v;
    } else {
      out.push_back(static_cast<std::uint8_t>(high << 4 | v));
      high = -1;
    }
  }
  if (high >= 0) throw std::runtime_error(path.string() + ": odd number of hex digits");
  return out;
}

}  // namespace

bool starts_with_magic(std::span<const std::uint8_t> b) {
  return b.size() >= 4 && b[0] == 0xEF && b[1] == 0xBE && b[2] == 0 && b[3] == 0;
}

Header read_header(std::span<const std::uint8_t> b) {
  return Header{le32(b, 0), le32(b, 4), le32(b, 8), le32(b, 12), le32(b, 16), le32(b, 20), le32(b, 24)};
}

void write_header(Bytes& f, const Header& h) {
  put_le32(f, 0, h.magic);
  put_le32(f, 4, h.version);
  put_le32(f, 8, h.total);
  put_le32(f, 12, h.thermal);
  put_le32(f, 16, h.jpeg);
  put_le32(f, 20, h.json);
  put_le32(f, 24, h.timestamp);
}

std::uint32_t frame_counter(std::span<const std::uint8_t> f) {
  return static_cast<std::uint32_t>(le16(f, kCounterAt)) |
         static_cast<std::uint32_t>(le16(f, kCounterAt + 2)) << 16;
}

void set_frame_counter(Bytes& f, std::uint32_t counter) {
  put_le16(f, kCounterAt, static_cast<std::uint16_t>(counter));
  put_le16(f, kCounterAt + 2, static_cast<std::uint16_t>(counter >> 16));
}

std::uint16_t packet_row(std::span<const std::uint8_t> f, std::size_t index) {
  return le16(f, kHeaderBytes + index * kPacketBytes) & 0x0FFF;
}

void set_packet_row(Bytes& f, std::size_t index, std::uint16_t row) {
  const std::size_t at = kHeaderBytes + index * kPacketBytes;
  put_le16(f, at, static_cast<std::uint16_t>((le16(f, at) & 0xF000) | (row & 0x0FFF)));
}

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) { return hil::fnv1a_add(hil::kFnvOffset, bytes.data(), bytes.size()); }

std::uint64_t image_hash(std::span<const std::uint8_t> frame) {
  std::uint64_t h = hil::kFnvOffset;
  for (std::size_t row = 0; row < kImageRows; ++row)
    h = hil::fnv1a_add(h, frame.data() + kHeaderBytes + row * kPacketBytes + 4, kWidth * 2);
  return h;
}

void seal_packets(Bytes& frame) {
  for (std::size_t p = 0; p < kPackets; ++p) {
    const std::size_t at = kHeaderBytes + p * kPacketBytes;
    std::uint16_t crc = 0;
    auto step = [&crc](std::uint8_t byte) {
      crc = static_cast<std::uint16_t>(crc ^ byte << 8);
      for (int bit = 0; bit < 8; ++bit)
        crc = static_cast<std::uint16_t>((crc & 0x8000) != 0 ? (crc << 1) ^ 0x1021 : crc << 1);
    };
    for (std::size_t w = 0; w < kPacketBytes / 2; ++w) {
      std::uint8_t high = frame[at + 2 * w + 1];
      std::uint8_t low = frame[at + 2 * w];
      if (w == 0) high &= 0x0F;
      if (w == 1) high = low = 0;
      step(high);
      step(low);
    }
    put_le16(frame, at + 2, crc);
  }
}

std::vector<Bytes> load_capture(const std::string& folder) {
  std::vector<std::pair<long, std::filesystem::path>> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string stem = entry.path().stem().string();
    if (entry.path().extension() != ".txt" || stem.empty() ||
        !std::all_of(stem.begin(), stem.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    files.emplace_back(std::stol(stem), entry.path());
  }
  if (files.empty()) throw std::runtime_error(folder + ": no N.txt transfer files");
  std::sort(files.begin(), files.end());
  std::vector<Bytes> transfers;
  for (const auto& [number, path] : files) transfers.push_back(parse_hex_file(path));
  return transfers;
}

std::vector<Bytes> split_frames(const std::vector<Bytes>& transfers) {
  Bytes all;
  for (const Bytes& t : transfers) all.insert(all.end(), t.begin(), t.end());
  std::vector<Bytes> frames;
  std::size_t at = 0;
  while (at + kHeaderBytes <= all.size()) {
    const std::span<const std::uint8_t> rest(all.data() + at, all.size() - at);
    if (!starts_with_magic(rest))
      throw std::runtime_error("capture: byte " + std::to_string(at) + ": no frame magic");
    const Header h = read_header(rest);
    if (h.thermal + h.jpeg + h.json != h.total || kHeaderBytes + h.total > rest.size())
      throw std::runtime_error("capture: byte " + std::to_string(at) + ": header lengths do not add up");
    frames.emplace_back(rest.begin(), rest.begin() + static_cast<std::ptrdiff_t>(kHeaderBytes + h.total));
    at += kHeaderBytes + h.total;
  }
  return frames;
}

SimulatedFrames::SimulatedFrames(Bytes base, std::size_t jpeg_bytes) : base_(std::move(base)) {
  Header h = read_header(base_);
  if (h.thermal != kThermalBytes || base_.size() != kHeaderBytes + h.total)
    throw std::runtime_error("simulated frames: the base frame is not a whole FLIR ONE frame");
  if (jpeg_bytes < h.jpeg) {
    const auto jpeg_at = static_cast<std::ptrdiff_t>(kHeaderBytes + h.thermal);
    base_.erase(base_.begin() + jpeg_at + static_cast<std::ptrdiff_t>(jpeg_bytes),
                base_.begin() + jpeg_at + static_cast<std::ptrdiff_t>(h.jpeg));
    h.jpeg = static_cast<std::uint32_t>(jpeg_bytes);
    h.total = h.thermal + h.jpeg + h.json;
    write_header(base_, h);
  }
}

Bytes SimulatedFrames::frame(std::uint64_t index, std::uint32_t counter) const {
  Bytes f = base_;
  Header h = read_header(f);
  h.timestamp = static_cast<std::uint32_t>(index * 116'000);  // ~8.6 Hz in µs
  write_header(f, h);
  // A warm blob drifting over a gradient, plus a per-pixel hash so that no two frames and no
  // two rows share bytes: a row delivered into the wrong place cannot go unnoticed.
  const auto cx = static_cast<std::int64_t>(index % 80);
  const auto cy = static_cast<std::int64_t>((index / 3) % 60);
  for (std::size_t row = 0; row < kImageRows; ++row) {
    const std::size_t at = kHeaderBytes + row * kPacketBytes + 4;
    for (std::size_t col = 0; col < kWidth; ++col) {
      const std::int64_t dx = static_cast<std::int64_t>(col) - cx;
      const std::int64_t dy = static_cast<std::int64_t>(row) - cy;
      const std::int64_t blob = dx * dx + dy * dy < 100 ? 1500 : 0;
      const std::uint64_t noise = (index * 0x9E3779B97F4A7C15ULL + row * 131 + col * 7919) >> 58;
      const auto v = static_cast<std::uint16_t>((7000 + 10 * static_cast<std::int64_t>(row) + blob +
                                                 static_cast<std::int64_t>(noise)) & 0x3FFF);
      put_le16(f, at + 2 * col, v);
    }
  }
  set_frame_counter(f, counter);
  seal_packets(f);
  return f;
}

}  // namespace bolo::hil::flirone
