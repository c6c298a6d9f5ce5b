#pragma once
// FaultInjector: a frame source that wraps another one and damages its stream the way real links
// do, at configured rates, so tests (and bench rigs on a board) can prove the pipeline survives:
//
//   drop           a frame is taken from the inner source and thrown away (the counter skips)
//   duplicate      a frame is delivered twice: same header, same sequence number, same pixels
//   reorder        two consecutive frames are delivered in swapped order (each keeps its header)
//   truncate       only the first k < height lines are delivered, then end_frame
//   corrupt        bits are flipped in 1 to 3 pixels of one line (within the source's `bits`)
//   missized line  one line is delivered with fewer or more pixels than the frame's width
//   repeated line  one line is delivered twice under its row index and the next row never comes
//                  (a line-counter glitch; the frame still has `height` lines)
//   ffc flip       the header's FFC flag is inverted (none/unknown -> completed, completed -> none)
//
// Every fault it injects is counted (`faults()`), and what happened to the frame just delivered
// is reported (`last_delivery()`), so a test knows exactly which frames are intact.
//
// Board-safe: no exceptions, no RTTI, every buffer allocated in the constructor (two frames and
// one line, sized from the inner source's format), nothing afterwards; deterministic from the
// seed on every target (splitmix64, integer rates).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bolo/core/frame_source.hpp"

namespace bolo::hal {

// Probability of each fault per frame, in parts per million (integers: the same seed gives the
// same faults on every target). 1'000'000 = always.
struct FaultRates {
  std::uint32_t drop = 0;
  std::uint32_t duplicate = 0;
  std::uint32_t reorder = 0;
  std::uint32_t truncate = 0;
  std::uint32_t corrupt = 0;
  std::uint32_t missized_line = 0;
  std::uint32_t repeated_line = 0;
  std::uint32_t ffc_flip = 0;
};

struct FaultInjectorConfig {
  std::uint64_t seed = 1;
  FaultRates rates;
  // After a delivery with any fault, this many deliveries stay clean: isolated faults whose
  // consequences can be counted one by one. 0 = faults may follow each other (and overlap).
  std::uint32_t quiet_after_fault = 0;
  // At most this many frames are dropped in a row before one is delivered (bounds the work of
  // one stream_frame call whatever the rates).
  std::uint32_t max_drop_burst = 3;
};

// Totals of what the injector did.
struct FaultCounts {
  std::uint64_t frames_in = 0;       // frames taken from the inner source
  std::uint64_t frames_out = 0;      // frames delivered (replays included)
  std::uint64_t dropped = 0;
  std::uint64_t duplicated = 0;      // second deliveries
  std::uint64_t reordered = 0;       // swapped pairs
  std::uint64_t truncated = 0;
  std::uint64_t corrupted = 0;       // frames with flipped bits
  std::uint64_t corrupted_pixels = 0;
  std::uint64_t missized_lines = 0;
  std::uint64_t repeated_lines = 0;
  std::uint64_t ffc_flipped_on = 0;   // none/unknown -> completed
  std::uint64_t ffc_flipped_off = 0;  // completed -> none
  // Not a fault: lines of the inner source that did not fit the storage sized from its format
  // (more than `height` lines, or longer than `width`); they are not passed on.
  std::uint64_t lines_lost = 0;
};

// What happened to the frame the last stream_frame() delivered.
struct DeliveryFaults {
  std::uint32_t dropped_before = 0;   // frames thrown away just before this one
  bool duplicate = false;             // this is the second delivery of the previous frame
  bool reordered = false;             // this frame swapped places with its neighbour
  bool truncated = false;
  std::uint32_t lines = 0;            // lines delivered (row indices as described below)
  bool corrupted = false;
  std::uint32_t corrupted_row = 0;
  bool missized_line = false;
  std::uint32_t missized_row = 0;
  std::uint32_t missized_length = 0;  // pixels in the mis-sized line
  bool repeated_line = false;
  std::uint32_t repeated_row = 0;     // delivered twice; repeated_row + 1 was never delivered
  bool ffc_flipped = false;
  bool lines_lost = false;            // the inner frame did not fit the storage

  // The frame's lines and header went out exactly as the inner source gave them (it may still
  // be a duplicate, reordered, or follow dropped frames: those change the stream, not the frame).
  bool frame_intact() const {
    return !truncated && !corrupted && !missized_line && !repeated_line && !ffc_flipped &&
           !lines_lost;
  }
  bool any() const { return !frame_intact() || dropped_before != 0 || duplicate || reordered; }
};

class FaultInjector final : public FrameSource {
 public:
  // `inner` must outlive the injector. Storage (two frames and a line of twice the width) is
  // sized here from inner.format() and never grows.
  FaultInjector(FrameSource& inner, const FaultInjectorConfig& config);
  FaultInjector(const FaultInjector&) = delete;
  FaultInjector& operator=(const FaultInjector&) = delete;

  SourceFormat format() const override { return format_; }
  // Pushes the next (possibly damaged) frame into `sink`. `fault` and `end_of_stream` of the
  // inner source are passed on; a frame held back for a reorder or a duplicate is still delivered
  // after the inner source ended.
  StreamStatus stream_frame(fw::LineSink& sink) override;
  // The inner source's statistics, with frames_delivered counting the frames delivered here.
  SourceStats stats() const override;
  ExtraCounters extra_counters() const override { return inner_.extra_counters(); }

  const FaultCounts& faults() const { return counts_; }
  const DeliveryFaults& last_delivery() const { return last_; }

 private:
  // One captured frame: its header and its lines in arrival order (row index, length, pixels).
  struct Slot {
    fw::FrameHeader header{};
    std::uint32_t lines = 0;
    bool lost = false;
    fw::Pixel* pixels = nullptr;   // height * width
    std::uint32_t* rows = nullptr;     // height
    std::uint32_t* lengths = nullptr;  // height
  };
  class Capture;

  std::uint64_t next_random();
  std::uint32_t below(std::uint32_t n);  // uniform enough in [0, n), n > 0
  bool roll(std::uint32_t rate_ppm);
  StreamStatus fetch(Slot& slot);
  void deliver(const Slot& slot, bool allow_faults, fw::LineSink& sink);

  FrameSource& inner_;
  FaultInjectorConfig config_;
  SourceFormat format_;
  std::uint64_t state_;  // splitmix64
  std::vector<fw::Pixel> pixels_;       // two frames + one scratch line of 2 * width
  std::vector<std::uint32_t> line_info_;  // rows and lengths of both slots
  Slot slots_[2];
  fw::Pixel* scratch_ = nullptr;
  int pending_ = -1;                // slot to deliver on the next call (duplicate / reorder)
  bool pending_is_duplicate_ = false;
  std::uint32_t quiet_ = 0;
  FaultCounts counts_;
  DeliveryFaults last_;
};

}  // namespace bolo::hal
