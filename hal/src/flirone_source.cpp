#include "bolo/hal/flirone_source.hpp"

namespace bolo::hal {

FlirOneSource::FlirOneSource(BulkInTransport& transport, const FlirOneSourceConfig& config)
    : transport_(transport),
      config_(config),
      reassembler_(config.max_frame_bytes, config.verify_crc),
      transfer_(config.transfer_bytes) {}

SourceFormat FlirOneSource::format() const {
  SourceFormat f;
  if (geometry_ == nullptr) geometry_ = &flirone::kGeometries[0];  // reported: the stream's from now on
  f.width = geometry_->width;
  f.height = geometry_->height;
  f.bits = 14;
  f.frame_period_ns = 116279070;  // ~8.6 frames/s exported
  return f;
}

ExtraCounters FlirOneSource::extra_counters() const {
  const FlirOneCounters& r = reassembler_.counters();
  ExtraCounters c;
  c.add("skipped_in_camera", skipped_in_camera_);
  c.add("counter_jumps", counter_.jumps());
  c.add("stray_transfers", r.stray_transfers);
  c.add("trailing_bytes", r.trailing_bytes);
  c.add("bad_status", r.bad_status);
  return c;
}

bool FlirOneSource::lost_frames_since(const FlirOneCounters& before) {
  const FlirOneCounters& now = reassembler_.counters();
  const std::uint64_t truncated = now.truncated - before.truncated;
  const std::uint64_t corrupt = (now.bad_header - before.bad_header) +
                                (now.bad_row_id - before.bad_row_id) +
                                (now.bad_crc - before.bad_crc);
  stats_.short_transfers += truncated;
  stats_.corrupt_transfers += corrupt;
  count_lost(truncated + corrupt);
  return truncated + corrupt > 0;
}

// A lost frame leaves a gap in the sequence, and is the wire's loss, not the camera's skip.
void FlirOneSource::count_lost(std::uint64_t frames) {
  sequence_ += frames;
  lost_since_good_ += frames;
}

// A counter step over n exported frames with s frames lost on the wire since the previous good
// frame: n - 1 frames are missing, s of them counted already (short, corrupt, each a gap in the
// sequence); the camera never sent the others (its core counted them but did not export them).
// Those leave a gap too: the frame after them is not its predecessor's successor on the sensor.
// Runs before the frame is numbered, so the gap falls in front of it.
void FlirOneSource::follow_frame_counter(std::uint32_t counter) {
  if (counter_.add(counter) == LeptonFrameCounter::Step::forward) {
    const std::uint32_t skipped = counter_.skipped_beyond(lost_since_good_);
    skipped_in_camera_ += skipped;
    sequence_ += skipped;
  }
  lost_since_good_ = 0;
}

bool FlirOneSource::probe() {
  if (held_) return held_status_ == StreamStatus::frame;
  held_status_ = next_whole_frame(held_arrival_ns_);
  held_ = true;
  if (held_status_ != StreamStatus::frame) return false;
  if (geometry_ == nullptr) geometry_ = reassembler_.frame().geometry;
  return true;
}

StreamStatus FlirOneSource::stream_frame(fw::LineSink& sink) {
  for (;;) {
    std::int64_t arrival_ns = held_arrival_ns_;
    const StreamStatus s = held_ ? held_status_ : next_whole_frame(arrival_ns);
    held_ = false;
    if (s != StreamStatus::frame) return s;
    const StreamStatus delivered = deliver(sink, arrival_ns);
    if (delivered != StreamStatus::end_of_stream) return delivered;  // else a skipped duplicate
  }
}

// Up to the next good frame, left in the reassembler (`frame`, with its arrival time), or what
// stopped it (fault, end_of_stream).
StreamStatus FlirOneSource::next_whole_frame(std::int64_t& arrival_ns) {
  for (;;) {
    FlirOneCounters before = reassembler_.counters();
    if (reassembler_.poll()) {
      lost_frames_since(before);
      arrival_ns = 0;
      return StreamStatus::frame;
    }
    if (lost_frames_since(before)) return StreamStatus::fault;

    const Transfer t = transport_.next(transfer_, config_.transfer_timeout_ms);
    switch (t.status) {
      case TransferStatus::ok: break;
      case TransferStatus::end: return StreamStatus::end_of_stream;
      case TransferStatus::timeout:
        // Counted, but what has arrived of a frame is kept: a device (or a loaded host) that
        // pauses mid-frame and then goes on completes it; one that goes on with the next frame
        // cuts it short, which the reassembler counts and drops when that frame's header comes.
        ++stats_.timeouts;
        return StreamStatus::fault;
      case TransferStatus::error:
        ++stats_.corrupt_transfers;
        if (reassembler_.buffered() > 0) count_lost(1);
        reassembler_.reset();
        return StreamStatus::fault;
      case TransferStatus::disconnected:
        if (connected_) {  // counted once per unplug, however long the device stays away
          ++stats_.disconnects;
          ++sequence_;  // a gap: nothing before the unplug is a predecessor of what follows
          reassembler_.reset();
          have_previous_ = false;  // the core restarts: no predecessor across an unplug
          ffc_.restart();
          counter_.restart();      // and counts from wherever it starts again
          lost_since_good_ = 0;
          connected_ = false;
        }
        if (transport_.reconnect(config_.reconnect_timeout_ms)) {
          ++stats_.reconnects;
          connected_ = true;
        }
        return StreamStatus::fault;
    }
    before = reassembler_.counters();
    const bool whole = reassembler_.push_transfer(std::span<const std::uint8_t>(transfer_.data(), t.bytes));
    const bool lost = lost_frames_since(before);
    if (whole) {
      arrival_ns = t.arrival_ns;
      return StreamStatus::frame;
    }
    if (lost) return StreamStatus::fault;
  }
}

// end_of_stream here means "nothing delivered, keep going" (a skipped duplicate).
StreamStatus FlirOneSource::deliver(fw::LineSink& sink, std::int64_t arrival_ns) {
  const FlirOneFrame& f = reassembler_.frame();
  if (geometry_ == nullptr) geometry_ = f.geometry;
  if (f.geometry != geometry_) {  // a core of another size mid-stream: not this stream's frame
    ++stats_.corrupt_transfers;
    count_lost(1);
    return StreamStatus::fault;
  }
  const std::uint32_t counter = f.lepton.frame_counter;
  follow_frame_counter(counter);
  // The previous frame's counter again, as before: the counter's repeats would also take one
  // delivered up to 63 frames back.
  const bool duplicate = have_previous_ && counter == previous_counter_;
  if (duplicate) ++stats_.duplicates;
  if (duplicate && config_.skip_duplicates) return StreamStatus::end_of_stream;

  fw::FrameHeader header;
  header.width = geometry_->width;
  header.height = geometry_->height;
  header.sequence = sequence_++;
  header.sequence_valid = true;
  if (config_.clock == FlirOneClock::camera) {
    header.timestamp_valid = f.status_ok && f.status.has_usb_timestamp;
    header.timestamp_ns = header.timestamp_valid ? f.status.usb_timestamp_ns : 0;
  } else {
    header.timestamp_valid = arrival_ns != 0;
    header.timestamp_ns = arrival_ns;
  }
  // The core stamps every shutter event with its time: a new stamp means one happened since the
  // previous frame; its status says one is imminent or in progress.
  header.ffc = ffc_.next(f.lepton);
  header.fpa_temp_mc = centikelvin_to_mc(f.lepton.fpa_temp_ck);
  header.housing_temp_mc = centikelvin_to_mc(f.lepton.housing_temp_ck);
  have_previous_ = true;
  previous_counter_ = counter;

  sink.begin_frame(header);
  sink.push_lines(0, geometry_->height, f.pixels, geometry_->width, geometry_->width);  // reassembled whole
  sink.end_frame();
  ++stats_.frames_delivered;
  return StreamStatus::frame;
}

}  // namespace bolo::hal
