#pragma once
// Host-side reassembly of FLIR ONE frames from bulk transfers: a frame starts with the magic at
// the start of a transfer, its header gives its length; a transfer that starts with the magic
// while a frame is still incomplete ends that frame as short. Whole frames are checked (header
// lengths, VoSPI packet rows in order) before they are handed out.

#include <cstdint>
#include <span>
#include <vector>

namespace bolo::hil::flirone {

enum class Piece : std::uint8_t { frame, short_frame, corrupt };

class FrameAssembler {
 public:
  // Feeds one transfer; each completed frame or fault is appended to `out` (frames' bytes to
  // `frames`, in the same order as their Piece::frame entries).
  void feed(std::span<const std::uint8_t> transfer, std::vector<Piece>& out,
            std::vector<std::vector<std::uint8_t>>& frames);
  // Drops a partial frame (after a timeout, stall or disconnect); true when there was one.
  bool drop_partial();

 private:
  bool check_header(std::vector<Piece>& out);
  std::vector<std::uint8_t> partial_;
  std::size_t expected_ = 0;  // whole frame size once the header is in
  bool resyncing_ = false;    // skipping transfers until one starts with the magic
};

}  // namespace bolo::hil::flirone
