#include "bolo/firmware/bad_pixel_stage.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "bolo/firmware/detail/kernels.hpp"

namespace bolo::fw {

BadPixelStage::BadPixelStage(const BadPixelConfig& config, std::span<Pixel> storage,
                             LineSink& next)
    : Stage(next), config_(config), width_(config.width), height_(config.height) {
  const std::size_t frame = std::size_t{width_} * height_;
  if (storage.size() < storage_pixels(width_, height_) ||
      (!config.mask.empty() && config.mask.size() < frame)) {
    width_ = 0;  // misconfigured: every frame passes through untouched
    height_ = 0;
    return;
  }
  ring_rows_ = ring_rows(width_);
  const std::size_t ring = std::size_t{width_} * ring_rows_;
  ring_ = storage.subspan(0, ring);
  out_line_ = storage.subspan(ring, width_);
  // Flag bits in the room storage_pixels() sets aside after the lines, accessed as bytes.
  std::uint8_t* const flag_room = reinterpret_cast<std::uint8_t*>(storage.data() + ring + width_);
  const std::size_t line_bytes = flag_words(width_) * 4;
  flags_ = std::span<std::uint8_t>(flag_room, ring_rows_ * line_bytes);
  if (!config.mask.empty()) {
    std::uint8_t* const mask_bits = flag_room + flags_.size();
    for (std::uint32_t row = 0; row < height_; ++row)
      detail::pack_mask_bits(config.mask.data() + std::size_t{row} * width_, width_,
                             mask_bits + std::size_t{row} * line_bytes);
    mask_bits_ = mask_bits;
  }
  config_.mask = {};  // not read again
}

BadPixelStage::BadPixelStage(const BadPixelConfig& config, const NucTables& input_nuc,
                             std::span<Pixel> storage, LineSink& next)
    : BadPixelStage(config, storage, next) {
  const std::size_t frame = std::size_t{width_} * height_;
  if (width_ == 0 || input_nuc.gain_q14.size() < frame || input_nuc.offset.size() < frame) {
    width_ = 0;
    height_ = 0;
    return;
  }
  nuc_tables_ = input_nuc;
  nuc_ = &nuc_tables_;
}

void BadPixelStage::begin_frame(const FrameHeader& header) {
  active_ = width_ != 0 && header.width == width_ && header.height == height_;
  nuc_frame_ = active_ && nuc_ != nullptr;
  rows_in_ = 0;
  stats_ = BadPixelFrameStats{};
  next().begin_frame(header);
}

namespace {

// n / d for d in 1..8 and n < 2^20 (at most 8 neighbours of 16 bits) by a reciprocal: with
// r = ceil(2^32 / d) = (2^32 + e) / d, e < d, the error n*e / (d*2^32) stays below 1/d because
// n*e < 2^32, so the floor is exact. A hardware divide costs more than the rest of a repair.
inline std::uint32_t divide_small(std::uint32_t n, std::uint32_t d) {
  static constexpr std::uint64_t kReciprocal[9] = {
      0, 0x100000000, 0x80000000, 0x55555556, 0x40000000, 0x33333334, 0x2AAAAAAB, 0x24924925,
      0x20000000};
  return static_cast<std::uint32_t>((n * kReciprocal[d]) >> 32);
}

// The 32 flag bits of pixels x & ~31 ... (x & ~31) + 31 of a row.
inline std::uint32_t flag_word(const std::uint8_t* row_flags, std::uint32_t x) {
  std::uint32_t word = 0;
  std::memcpy(&word, row_flags + std::size_t{x / 32} * 4, sizeof word);
  return word;
}

inline bool flagged(const std::uint8_t* row_flags, std::uint32_t x) {
  return ((flag_word(row_flags, x) >> (x % 32)) & 1u) != 0;
}

}  // namespace

void BadPixelStage::push_line(std::uint32_t row, LineView line) {
  if (!active_ || row != rows_in_ || row >= height_ || line.size() != width_) {
    // Out of order or mis-sized: the neighbourhood is meaningless, so stop repairing this frame
    // but still deliver what is buffered in order.
    if (active_ && rows_in_ > 0) emit(rows_in_ - 1);
    active_ = false;
    pass_through(row, line);
    return;
  }
  ingest(row, line.data());
  if (row >= kRadius) emit(row - kRadius);
}

void BadPixelStage::push_lines(std::uint32_t first_row, std::uint32_t count, const Pixel* pixels,
                               std::size_t width, std::size_t stride) {
  // An empty run is nothing to do (and `first_row + count - 1` below would wrap).
  if (count == 0) return;
  if (!active_ || first_row != rows_in_ || width != width_ || count > height_ - first_row) {
    LineSink::push_lines(first_row, count, pixels, width, stride);  // push_line decides
    return;
  }
  // Rows ready = ingested with their successor; they leave in the order and state push_line
  // would give them (each repaired after the row below it arrived), only several per call.
  // A run of ready rows goes before the next ingest would overwrite the line above its first
  // row (a neighbour), and before it would wrap around the ring's end (runs are contiguous).
  // The rows between two such flushes are ingested in one call (they go to consecutive ring
  // lines: a batch ends at the ring's last line at the latest, and a row in line 0 flushes).
  const std::uint32_t last = first_row + count - 1;
  std::uint32_t ready = first_row == 0 ? 0 : first_row - 1;  // first row not yet handed on
  const auto flushes_after = [&](std::uint32_t row) {
    return row != ready && (row - ready >= ring_rows_ - 2 || (row & (ring_rows_ - 1)) == 0 ||
                            row == last);
  };
  // The first row at or after `row` that flushes (rows >= ready): the last row, the row
  // ring_rows_ - 2 after `ready`, or the next row in line 0 other than `ready` itself.
  const std::uint32_t slot_mask = ring_rows_ - 1;
  const auto next_flush = [&](std::uint32_t row) {
    std::uint32_t line0 = (row + slot_mask) & ~slot_mask;
    if (line0 == ready) line0 += ring_rows_;
    return std::min({last, std::max(row, ready + ring_rows_ - 2), line0});
  };
  for (std::uint32_t row = first_row; row <= last;) {
    const std::uint32_t room = ring_rows_ - (row & slot_mask);  // lines to the ring's end
    // The batch: row ... end, up to the next flush or the ring's end (what stepping `end` on
    // while !flushes_after(end) would give, without a test per row).
    const std::uint32_t end = std::min(next_flush(row), row + room - 1);
    ingest_run(row, end - row + 1, pixels + std::size_t{row - first_row} * stride, stride);
    if (flushes_after(end)) {
      repair_rows(ready, end - ready);
      next().push_lines(ready, end - ready, ring_line(ready), width_, width_);
      ready = end;
    }
    row = end + 1;
  }
}

detail::IngestLine BadPixelStage::ingest_job(std::uint32_t row, const Pixel* input) {
  const std::size_t at = std::size_t{row} * width_;
  const std::uint8_t* mask_bits =
      mask_bits_ == nullptr ? nullptr : mask_bits_ + std::size_t{row} * flag_words(width_) * 4;
  detail::IngestLine job{input, nullptr, nullptr, mask_bits, config_.detect_stuck,
                         config_.stuck_low, config_.stuck_high, ring_line(row), ring_flags(row),
                         width_, std::size_t{width_} * height_ >= kPrefetchFromPixels};
  if (nuc_ != nullptr) {
    job.gain_q14 = nuc_->gain_q14.data() + at;
    job.offset = nuc_->offset.data() + at;
  }
  return job;
}

void BadPixelStage::ingest(std::uint32_t row, const Pixel* line) {
  const detail::IngestLine job = ingest_job(row, line);
  const std::uint64_t bit = std::uint64_t{1} << (row & (ring_rows_ - 1));
  row_flagged_ = detail::ingest_line(job) ? row_flagged_ | bit : row_flagged_ & ~bit;
  rows_in_ = row + 1;
}

// Rows row ... row + count - 1 into consecutive ring lines (the caller keeps them from wrapping).
void BadPixelStage::ingest_run(std::uint32_t row, std::uint32_t count, const Pixel* lines,
                               std::size_t stride) {
  const detail::IngestLine job = ingest_job(row, lines);
  const std::uint32_t slot = row & (ring_rows_ - 1);
  const std::uint64_t lines_mask = (count == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << count) - 1)
                                   << slot;
  const std::uint64_t flagged = detail::ingest_rows(job, count, stride) << slot;
  row_flagged_ = (row_flagged_ & ~lines_mask) | flagged;
  rows_in_ = row + count;
}

void BadPixelStage::emit(std::uint32_t row) {
  repair_row(row);
  // The ring line itself goes on: it is not touched before the next push.
  next().push_line(row, LineView(ring_line(row), width_));
}

// Repairs in place in the ring: a repaired pixel is flagged, and flagged pixels are never read as
// neighbours, so the rows still to come see the same neighbourhoods as with a copy.
void BadPixelStage::repair_row(std::uint32_t row) {
  if ((row_flagged_ >> (row & (ring_rows_ - 1))) & 1u) repair_flagged_row(row);
}

// Rows first ... first + count - 1, consecutive ring lines (a run about to leave): only the rows
// whose bit in row_flagged_ is set are looked at, without a call per row.
void BadPixelStage::repair_rows(std::uint32_t first, std::uint32_t count) {
  std::uint64_t rows = row_flagged_ >> (first & (ring_rows_ - 1));
  if (count < 64) rows &= (std::uint64_t{1} << count) - 1;
  for (; rows != 0; rows &= rows - 1)
    repair_flagged_row(first + static_cast<std::uint32_t>(std::countr_zero(rows)));
}

void BadPixelStage::repair_flagged_row(std::uint32_t row) {
  const std::uint8_t* centre_flags = ring_flags(row);
  // Only flagged pixels change: the set bits of each flag word, lowest first. The scan stays
  // a tight loop; the (rare) repair is a call.
  for (std::uint32_t base = 0; base < width_; base += 32) {
    for (std::uint32_t bits = flag_word(centre_flags, base); bits != 0; bits &= bits - 1)
      repair(row, base + static_cast<std::uint32_t>(std::countr_zero(bits)));
  }
}

void BadPixelStage::repair(std::uint32_t row, std::uint32_t x) {
  const std::uint32_t first = row == 0 ? 0 : row - 1;
  const std::uint32_t last = std::min(row + 1, rows_in_ - 1);
  const std::uint32_t x0 = x == 0 ? 0 : x - 1;
  const std::uint32_t x1 = std::min(x + 1, width_ - 1);
  std::uint32_t sum = 0;
  std::uint32_t count = 0;
  for (std::uint32_t r = first; r <= last; ++r) {
    const Pixel* values = ring_line(r);
    const std::uint8_t* flags = ring_flags(r);
    for (std::uint32_t c = x0; c <= x1; ++c) {
      if (!flagged(flags, c)) {
        sum += values[c];
        ++count;
      }
    }
  }
  if (count == 0) {
    ++stats_.unrepairable;  // passed through unchanged
  } else {
    ring_line(row)[x] = static_cast<Pixel>(divide_small(sum + count / 2, count));  // nearest, ties up
    ++stats_.replaced;
  }
}

// A line the neighbourhood rule does not take: unchanged, or only through the NUC where a
// NucStage in front would have applied it (a line of this frame's size, within its height).
void BadPixelStage::pass_through(std::uint32_t row, LineView line) {
  if (nuc_frame_ && row < height_ && line.size() == width_) {
    const std::size_t at = std::size_t{row} * width_;
    nuc_line(line.data(), nuc_->gain_q14.data() + at, nuc_->offset.data() + at, out_line_.data(),
             width_);
    next().push_line(row, LineView(out_line_.data(), width_));
    return;
  }
  next().push_line(row, line);
}

void BadPixelStage::end_frame() {
  if (active_ && rows_in_ > 0) emit(rows_in_ - 1);
  active_ = false;
  next().end_frame();
}

}  // namespace bolo::fw
