#include "bolo/hal/flirone_reassembler.hpp"

#include <cstring>

#include "bolo/hal/vospi_crc.hpp"

namespace bolo::hal {

using namespace flirone;

const Geometry* flirone::geometry_for(std::size_t thermal_bytes) {
  for (const Geometry& g : kGeometries)
    if (g.thermal_bytes == thermal_bytes) return &g;
  return nullptr;
}

namespace {
std::size_t largest_thermal() {
  std::size_t most = 0;
  for (const Geometry& g : kGeometries) most = g.thermal_bytes > most ? g.thermal_bytes : most;
  return most;
}
}  // namespace

bool flirone_starts_frame(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= 4 && read_le32(bytes.data()) == kMagic;
}

FlirOneReassembler::FlirOneReassembler(std::size_t max_frame_bytes, bool verify_crc)
    : buffer_(max_frame_bytes < kHeaderBytes + largest_thermal() ? kHeaderBytes + largest_thermal()
                                                                 : max_frame_bytes),
      verify_crc_(verify_crc) {}

// The delivered frame stays in the buffer until the caller is done with frame().jpeg.
void FlirOneReassembler::drop_delivered() {
  if (consumed_ == 0) return;
  const std::size_t rest = have_ - consumed_;
  if (rest > 0) std::memmove(buffer_.data(), buffer_.data() + consumed_, rest);
  have_ = rest;
  consumed_ = 0;
}

bool FlirOneReassembler::push_transfer(std::span<const std::uint8_t> transfer) {
  drop_delivered();
  if (transfer.empty()) return false;  // zero-length transfers are normal between frames
  if (flirone_starts_frame(transfer)) {
    if (have_ > 0) ++counters_.truncated;
    have_ = 0;
  } else if (have_ == 0) {
    ++counters_.stray_transfers;
    return false;
  }
  const std::size_t room = buffer_.size() - have_;
  const std::size_t take = transfer.size() < room ? transfer.size() : room;
  std::memcpy(buffer_.data() + have_, transfer.data(), take);
  have_ += take;
  // A frame always fits (the header check bounds it by the buffer), so bytes that do not are
  // past a frame's end.
  if (take < transfer.size()) counters_.trailing_bytes += transfer.size() - take;
  return complete_if_whole();
}

bool FlirOneReassembler::poll() {
  drop_delivered();
  return have_ > 0 && complete_if_whole();
}

bool FlirOneReassembler::complete_if_whole() {
  if (have_ < kHeaderBytes) return false;
  const std::uint8_t* h = buffer_.data();
  const std::uint32_t total = read_le32(h + 8), thermal = read_le32(h + 12);
  const std::uint32_t jpeg = read_le32(h + 16), json = read_le32(h + 20);
  const std::uint64_t parts = std::uint64_t{thermal} + jpeg + json;
  if (read_le32(h) != kMagic || geometry_for(thermal) == nullptr || parts != total ||
      total > buffer_.size() - kHeaderBytes) {
    ++counters_.bad_header;
    have_ = 0;
    return false;
  }
  const std::size_t end = kHeaderBytes + total;
  if (have_ < end) return false;

  const bool good = decode(std::span<const std::uint8_t>(buffer_.data(), end));
  const std::size_t rest = have_ - end;
  if (rest > 0 && !flirone_starts_frame(std::span<const std::uint8_t>(buffer_.data() + end, rest))) {
    counters_.trailing_bytes += rest;
    have_ = end;
  }
  consumed_ = end;
  if (good) ++counters_.frames;
  return good;
}

bool FlirOneReassembler::decode(std::span<const std::uint8_t> bytes) {
  const std::uint8_t* h = bytes.data();
  const std::uint8_t* thermal = h + kHeaderBytes;
  const Geometry& g = *geometry_for(read_le32(h + 12));
  bool rows_ok = true, crc_ok = true;
  for (std::size_t p = 0; g.vospi_packets && p < kPackets; ++p) {
    const std::uint8_t* packet = thermal + p * kPacketBytes;
    const std::uint16_t id = static_cast<std::uint16_t>(packet[0] | (packet[1] << 8));
    if ((id & 0x0FFFu) != p) rows_ok = false;
    if (verify_crc_) {
      const std::uint16_t crc = static_cast<std::uint16_t>(packet[2] | (packet[3] << 8));
      if (vospi_crc_le_words(std::span<const std::uint8_t>(packet, kPacketBytes)) != crc)
        crc_ok = false;
    }
  }
  if (!rows_ok) ++counters_.bad_row_id;
  if (rows_ok && !crc_ok) ++counters_.bad_crc;
  if (!rows_ok || !crc_ok) return false;

  FlirOneFrame& f = frame_;
  f.total_bytes = read_le32(h + 8);
  f.jpeg_bytes = read_le32(h + 16);
  f.json_bytes = read_le32(h + 20);
  f.header_timestamp = read_le32(h + 24);
  f.geometry = &g;
  // Both layouts are rows of 80-pixel runs behind a 4-byte prefix (a VoSPI packet's id and CRC,
  // or a 160x120 row's half), `runs` of them per image row.
  const std::size_t runs = g.width / kWidth;
  for (std::size_t r = 0; r < g.height + g.telemetry_rows; ++r) {
    std::uint16_t* out = r < g.height ? &f.pixels[r * g.width] : f.telemetry[r - g.height];
    for (std::size_t run = 0; run < runs; ++run) {
      const std::uint8_t* px = thermal + (r * runs + run) * kPacketBytes + 4;
      for (std::size_t x = 0; x < kWidth; ++x)
        out[run * kWidth + x] = static_cast<std::uint16_t>(px[2 * x] | (px[2 * x + 1] << 8));
    }
  }
  f.lepton = LeptonTelemetry{};
  decode_lepton_telemetry(std::span<const std::uint16_t>(f.telemetry[0], kWidth), f.lepton);
  const std::uint8_t* jpeg = thermal + g.thermal_bytes;
  f.jpeg = std::span<const std::uint8_t>(jpeg, f.jpeg_bytes);
  f.status = FlirOneStatus{};
  f.status_ok = f.json_bytes > 0 &&
                parse_flirone_status(std::span<const std::uint8_t>(jpeg + f.jpeg_bytes, f.json_bytes),
                                     f.status);
  if (!f.status_ok) ++counters_.bad_status;
  return true;
}

}  // namespace bolo::hal
