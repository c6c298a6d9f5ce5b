#include "bolo/hal/fault_injector.hpp"

#include <algorithm>

namespace bolo::hal {

namespace {

constexpr std::uint32_t kAlways = 1'000'000;  // rates are parts per million

}  // namespace

// Captures one frame of the inner source into a slot: the header, and every line that fits the
// storage (at most `height` lines of at most `width` pixels), in arrival order.
class FaultInjector::Capture final : public fw::LineSink {
 public:
  Capture(Slot& slot, std::uint32_t width, std::uint32_t height)
      : slot_(slot), width_(width), height_(height) {
    slot_.header = fw::FrameHeader{};
    slot_.lines = 0;
    slot_.lost = false;
  }
  void begin_frame(const fw::FrameHeader& header) override {
    slot_.header = header;
    slot_.lines = 0;
    slot_.lost = false;
  }
  void push_line(std::uint32_t row, fw::LineView line) override {
    if (slot_.lines >= height_ || line.size() > width_) {
      slot_.lost = true;
      ++lost_;
      return;
    }
    std::copy(line.begin(), line.end(), slot_.pixels + std::size_t{slot_.lines} * width_);
    slot_.rows[slot_.lines] = row;
    slot_.lengths[slot_.lines] = static_cast<std::uint32_t>(line.size());
    ++slot_.lines;
  }
  void end_frame() override {}
  std::uint64_t lost() const { return lost_; }

 private:
  Slot& slot_;
  std::uint32_t width_;
  std::uint32_t height_;
  std::uint64_t lost_ = 0;
};

FaultInjector::FaultInjector(FrameSource& inner, const FaultInjectorConfig& config)
    : inner_(inner), config_(config), format_(inner.format()), state_(config.seed) {
  const std::size_t width = format_.width;
  const std::size_t height = format_.height;
  const std::size_t frame = width * height;
  pixels_.resize(2 * frame + 2 * width);
  line_info_.resize(4 * height);
  for (std::size_t s = 0; s < 2; ++s) {
    slots_[s].pixels = pixels_.data() + s * frame;
    slots_[s].rows = line_info_.data() + (2 * s) * height;
    slots_[s].lengths = line_info_.data() + (2 * s + 1) * height;
  }
  scratch_ = pixels_.data() + 2 * frame;
}

SourceStats FaultInjector::stats() const {
  SourceStats s = inner_.stats();
  s.frames_delivered = counts_.frames_out;
  return s;
}

// splitmix64: tiny, and the same numbers on every target.
std::uint64_t FaultInjector::next_random() {
  std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint32_t FaultInjector::below(std::uint32_t n) {
  // The high 32 bits scaled to [0, n): multiply-shift, no division.
  return static_cast<std::uint32_t>(((next_random() >> 32) * n) >> 32);
}

bool FaultInjector::roll(std::uint32_t rate_ppm) {
  if (rate_ppm == 0) return false;
  if (rate_ppm >= kAlways) return true;
  return below(kAlways) < rate_ppm;
}

StreamStatus FaultInjector::fetch(Slot& slot) {
  Capture capture(slot, format_.width, format_.height);
  const StreamStatus status = inner_.stream_frame(capture);
  counts_.lines_lost += capture.lost();
  if (status == StreamStatus::frame) ++counts_.frames_in;
  return status;
}

void FaultInjector::deliver(const Slot& slot, bool allow_faults, fw::LineSink& sink) {
  DeliveryFaults& d = last_;
  fw::FrameHeader header = slot.header;
  std::uint32_t lines = slot.lines;
  d.lines_lost = slot.lost;
  // Which captured line goes out at position i: itself, except after a repeated line.
  const auto source_line = [&d](std::uint32_t i) {
    return d.repeated_line && i == d.repeated_row + 1 ? d.repeated_row : i;
  };
  if (allow_faults) {
    if (roll(config_.rates.ffc_flip)) {
      d.ffc_flipped = true;
      if (fw::shutter_event(header.ffc)) {
        header.ffc = fw::FfcState::none;
        ++counts_.ffc_flipped_off;
      } else {
        header.ffc = fw::FfcState::completed;
        ++counts_.ffc_flipped_on;
      }
    }
    if (lines > 0 && roll(config_.rates.truncate)) {
      lines = below(lines);  // 0 .. lines - 1
      d.truncated = true;
      ++counts_.truncated;
    }
    if (lines > 1 && roll(config_.rates.repeated_line)) {
      d.repeated_line = true;
      d.repeated_row = below(lines - 1);
      ++counts_.repeated_lines;
    }
    if (lines > 0 && roll(config_.rates.corrupt)) {
      const std::uint32_t at = below(lines);
      if (slot.lengths[source_line(at)] > 0) {
        d.corrupted = true;
        d.corrupted_row = at;
        ++counts_.corrupted;
      }
    }
    if (lines > 0 && format_.width > 0 && roll(config_.rates.missized_line)) {
      const std::uint32_t at = below(lines);
      const std::uint32_t length = slot.lengths[source_line(at)];
      d.missized_line = true;
      d.missized_row = at;
      // Shorter (0 .. length-1) or longer (length+1 .. length+width); the scratch line holds 2W.
      d.missized_length =
          length > 0 && below(2) == 0 ? below(length) : length + 1 + below(format_.width);
      ++counts_.missized_lines;
    }
  }
  d.lines = lines;

  sink.begin_frame(header);
  const std::uint32_t bits = format_.bits >= 1 && format_.bits <= 16 ? format_.bits : 16;
  for (std::uint32_t i = 0; i < lines; ++i) {
    const std::uint32_t src = source_line(i);
    const fw::Pixel* data = slot.pixels + std::size_t{src} * format_.width;
    const std::uint32_t length = slot.lengths[src];
    const bool corrupt_here = d.corrupted && i == d.corrupted_row;
    const bool missize_here = d.missized_line && i == d.missized_row;
    if (!corrupt_here && !missize_here) {
      sink.push_line(slot.rows[src], fw::LineView(data, length));
      continue;
    }
    std::copy(data, data + length, scratch_);
    if (corrupt_here) {
      // 1 to 3 distinct pixels, one bit each: the line always differs from the original.
      const std::uint32_t count = std::min<std::uint32_t>(1 + below(3), length);
      const std::uint32_t first = below(length);
      for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t x = (first + k) % length;
        scratch_[x] = static_cast<fw::Pixel>(scratch_[x] ^ (1u << below(bits)));
      }
      counts_.corrupted_pixels += count;
    }
    std::uint32_t out_length = length;
    if (missize_here) {
      out_length = d.missized_length;
      for (std::uint32_t x = length; x < out_length; ++x)
        scratch_[x] = length > 0 ? scratch_[x % length] : fw::Pixel{0};
    }
    sink.push_line(slot.rows[src], fw::LineView(scratch_, out_length));
  }
  sink.end_frame();
  ++counts_.frames_out;
}

StreamStatus FaultInjector::stream_frame(fw::LineSink& sink) {
  last_ = DeliveryFaults{};
  if (pending_ >= 0) {  // the second half of a duplicate or a reorder
    const Slot& slot = slots_[pending_];
    pending_ = -1;
    if (pending_is_duplicate_) {
      last_.duplicate = true;
      ++counts_.duplicated;
      deliver(slot, false, sink);  // a duplicate is the frame exactly as the source gave it
    } else {
      last_.reordered = true;
      deliver(slot, config_.quiet_after_fault == 0, sink);
    }
    quiet_ = config_.quiet_after_fault;
    return StreamStatus::frame;
  }

  const bool may_fault = quiet_ == 0;
  if (!may_fault) --quiet_;
  std::uint32_t dropped = 0;
  while (may_fault && dropped < config_.max_drop_burst && roll(config_.rates.drop)) {
    const StreamStatus status = fetch(slots_[0]);
    if (status != StreamStatus::frame) return status;
    ++dropped;
    ++counts_.dropped;
  }
  const StreamStatus status = fetch(slots_[0]);
  if (status != StreamStatus::frame) return status;
  last_.dropped_before = dropped;

  if (may_fault && roll(config_.rates.reorder)) {
    // The next frame goes first; this one waits for the next call. Without a next frame (the
    // inner source ended or lost one) this one goes out in order.
    if (fetch(slots_[1]) == StreamStatus::frame) {
      ++counts_.reordered;
      last_.reordered = true;
      deliver(slots_[1], true, sink);
      pending_ = 0;
      pending_is_duplicate_ = false;
      return StreamStatus::frame;
    }
  } else if (may_fault && roll(config_.rates.duplicate)) {
    pending_ = 0;
    pending_is_duplicate_ = true;
  }
  deliver(slots_[0], may_fault, sink);
  if (pending_ < 0 && last_.any()) quiet_ = config_.quiet_after_fault;
  return StreamStatus::frame;
}

}  // namespace bolo::hal
