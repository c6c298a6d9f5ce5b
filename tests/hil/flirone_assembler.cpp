#include "flirone_assembler.hpp"

#include <algorithm>

#include "emulators/flirone_frames.hpp"

namespace bolo::hil::flirone {

namespace {
constexpr std::size_t kMaxFrameBytes = 1u << 20;
}

bool FrameAssembler::drop_partial() {
  const bool had = !partial_.empty();
  partial_.clear();
  expected_ = 0;
  return had;
}

bool FrameAssembler::check_header(std::vector<Piece>& out) {
  const Header h = read_header(partial_);
  const bool sane = h.version == 1 && h.thermal == kThermalBytes &&
                    static_cast<std::uint64_t>(h.thermal) + h.jpeg + h.json == h.total &&
                    kHeaderBytes + h.total <= kMaxFrameBytes;
  if (!sane) {
    out.push_back(Piece::corrupt);
    drop_partial();
    resyncing_ = true;
    return false;
  }
  expected_ = kHeaderBytes + h.total;
  return true;
}

void FrameAssembler::feed(std::span<const std::uint8_t> t, std::vector<Piece>& out,
                          std::vector<std::vector<std::uint8_t>>& frames) {
  if (starts_with_magic(t)) {
    resyncing_ = false;
    if (!partial_.empty()) {
      out.push_back(Piece::short_frame);
      drop_partial();
    }
  }
  if (resyncing_) return;
  std::size_t at = 0;
  while (at < t.size()) {
    if (partial_.empty() && !starts_with_magic(t.subspan(at))) {
      // Bytes where a frame should start: the stream lost its framing; wait for the magic.
      out.push_back(Piece::corrupt);
      resyncing_ = true;
      return;
    }
    const std::size_t want = expected_ == 0 ? kHeaderBytes - partial_.size() : expected_ - partial_.size();
    const std::size_t n = std::min(want, t.size() - at);
    partial_.insert(partial_.end(), t.begin() + static_cast<std::ptrdiff_t>(at),
                    t.begin() + static_cast<std::ptrdiff_t>(at + n));
    at += n;
    if (expected_ == 0 && partial_.size() == kHeaderBytes && !check_header(out)) return;
    if (expected_ != 0 && partial_.size() == expected_) {
      bool rows_ok = true;
      for (std::size_t p = 0; p < kPackets && rows_ok; ++p) rows_ok = packet_row(partial_, p) == p;
      if (rows_ok) {
        out.push_back(Piece::frame);
        frames.push_back(std::move(partial_));
      } else {
        out.push_back(Piece::corrupt);
      }
      drop_partial();
    }
  }
}

}  // namespace bolo::hil::flirone
