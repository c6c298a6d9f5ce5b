#include "bolo/hal/seek_source.hpp"

namespace bolo::hal {
namespace {

bool ok(const Transfer& t) { return t.status == TransferStatus::ok; }

}  // namespace

SeekSource::SeekSource(VendorUsbTransport& transport, const SeekModel& model, const SeekSourceConfig& config)
    : transport_(transport), config_(config), parser_(model), chunk_(model.chunk_bytes) {}

SeekSource::~SeekSource() {
  if (started_) {
    const std::uint8_t idle[2] = {0, 0};
    transport_.control_out(seek::kSetOperationMode, idle);
  }
}

SourceFormat SeekSource::format() const {
  SourceFormat f;
  f.width = parser_.model().width;
  f.height = parser_.model().image_height();
  f.bits = 16;
  f.frame_period_ns = 1'000'000'000u / parser_.model().max_fps;
  return f;
}

ExtraCounters SeekSource::extra_counters() const {
  ExtraCounters c;
  c.add("shutter_frames", counters_.shutter_frames);
  c.add("calibration_frames", counters_.calibration_frames);
  c.add("startup_frames", counters_.startup_frames);
  c.add("start_failures", counters_.start_failures);
  c.add("counter_jumps", counters_.counter_jumps);
  return c;
}

// The start-up sequence of usb-thermal-cores.md. The factory-settings write/read pairs are not
// sent: the facts do not give their payloads.
TransferStatus SeekSource::start() {
  const std::uint8_t platform[1] = {1}, idle[2] = {0, 0}, processing[2] = {8, 0}, run[2] = {1, 0};
  TransferStatus last = TransferStatus::error;
  for (int attempt = 0; attempt < 2; ++attempt) {
    last = transport_.control_out(seek::kTargetPlatform, platform).status;
    if (last == TransferStatus::disconnected) break;
    if (last != TransferStatus::ok) {
      transport_.control_out(seek::kSetOperationMode, idle);  // close, then try once more
      continue;
    }
    const TransferStatus steps[] = {
        transport_.control_out(seek::kSetOperationMode, idle).status,
        transport_.control_in(seek::kGetFirmwareInfo, firmware_).status,
        transport_.control_in(seek::kReadChipId, chip_id_).status,
        transport_.control_out(seek::kSetImageProcessingMode, processing).status,
        transport_.control_out(seek::kSetOperationMode, run).status};
    last = TransferStatus::ok;
    for (TransferStatus s : steps)
      if (s != TransferStatus::ok && last == TransferStatus::ok) last = s;
    if (last == TransferStatus::ok) {
      started_ = true;
      return last;
    }
    if (last == TransferStatus::disconnected) break;
  }
  ++counters_.start_failures;
  return last;
}

bool SeekSource::request_shutter() {
  const std::uint8_t toggle[4] = {0xFC, 0x00, 0x04, 0x00};
  return ok(transport_.control_out(seek::kToggleShutter, toggle));
}

// Asks for one frame: START_GET_IMAGE_TRANSFER with the pixel count (LE32).
Transfer SeekSource::request_frame() {
  const std::uint32_t pixels = parser_.model().pixels();
  const std::uint8_t count[4] = {static_cast<std::uint8_t>(pixels), static_cast<std::uint8_t>(pixels >> 8),
                                 static_cast<std::uint8_t>(pixels >> 16), static_cast<std::uint8_t>(pixels >> 24)};
  const Transfer request = transport_.control_out(seek::kStartGetImageTransfer, count);
  if (ok(request)) {
    parser_.begin();
    silent_timeouts_ = 0;
  }
  return request;
}

// The frame asked for, or what became of it. A frame still awaited after a timeout (`waiting`)
// keeps what has arrived and is read on at the next call, without asking again.
SeekSource::Read SeekSource::read_frame(std::int64_t& arrival_ns) {
  if (!frame_requested_) {
    const Transfer request = request_frame();
    if (request.status == TransferStatus::disconnected) return Read::gone;
    if (!ok(request)) {
      ++stats_.corrupt_transfers;
      return Read::lost;
    }
    frame_requested_ = true;
  }
  const Read r = read_chunks(arrival_ns);
  frame_requested_ = r == Read::waiting;
  return r;
}

SeekSource::Read SeekSource::read_chunks(std::int64_t& arrival_ns) {
  for (;;) {
    const Transfer t = transport_.next(chunk_, config_.transfer_timeout_ms);
    switch (t.status) {
      case TransferStatus::ok: silent_timeouts_ = 0; break;
      case TransferStatus::timeout: return on_timeout();
      case TransferStatus::error: ++stats_.corrupt_transfers; return Read::lost;
      case TransferStatus::disconnected:
      case TransferStatus::end: return Read::gone;
    }
    switch (parser_.add_chunk({chunk_.data(), t.bytes})) {
      case SeekChunk::need_more: continue;
      case SeekChunk::complete: arrival_ns = t.arrival_ns; return Read::frame;
      case SeekChunk::aborted: ++stats_.short_transfers; return Read::lost;
      case SeekChunk::overflow: ++stats_.corrupt_transfers; return Read::lost;
    }
  }
}

// A pause (the camera's, or a loaded host's) is counted and waited out: the camera sends nothing
// it was not asked for, so whatever comes next without a new request is the rest of this frame.
// Silent for timeouts_before_giving_up in a row, the camera has abandoned it: a frame that had
// begun is counted short, and the next call asks anew.
SeekSource::Read SeekSource::on_timeout() {
  ++stats_.timeouts;
  if (++silent_timeouts_ < config_.timeouts_before_giving_up) return Read::waiting;
  if (parser_.received() > 0) ++stats_.short_transfers;
  return Read::lost;
}

// After a lost frame the camera may still send the rest of it (a transfer error mid-frame, or a
// pause longer than the patience above), ahead of the frame asked for next; the chunks would then
// assemble into a frame that begins mid-frame. Such a frame's type word is pixel data.
bool SeekSource::starts_a_frame(const SeekFrameInfo& info) const { return seek_frame_type_known(info.type); }

// Drops what the camera is still sending until it is silent, so that the next request's frame
// starts at its first chunk. The frame assembled from the stale chunks is counted corrupt.
StreamStatus SeekSource::resynchronise() {
  ++stats_.corrupt_transfers;
  ++sequence_;
  const std::size_t chunks_per_frame = (parser_.model().frame_bytes() + chunk_.size() - 1) / chunk_.size();
  for (std::size_t n = 0; n < 2 * chunks_per_frame; ++n) {
    const Transfer t = transport_.next(chunk_, config_.transfer_timeout_ms);
    if (t.status == TransferStatus::disconnected) return device_gone();
    if (t.status != TransferStatus::ok) break;  // silent (the wait was the point, not a fault)
  }
  return StreamStatus::fault;
}

// Every frame the camera sends (images, shutter and calibration frames) carries the next counter
// value. Returns whether this frame repeats the previous one's.
bool SeekSource::follow_counter(const SeekFrameInfo& info) {
  const bool had = have_counter_;
  const std::uint16_t step = static_cast<std::uint16_t>(info.counter - previous_counter_);
  have_counter_ = true;
  previous_counter_ = info.counter;
  if (!had || step == 1) return false;
  if (step == 0) return true;
  ++counters_.counter_jumps;
  if (step - 1 <= kSeekPlausibleGap) stats_.dropped += step - 1u;
  return false;
}

StreamStatus SeekSource::device_gone() {
  have_counter_ = false;  // a replugged camera boots and counts again
  frame_requested_ = false;
  check_alignment_ = false;  // and sends nothing left over from before
  if (connected_) {  // counted once per unplug, however long the camera stays away
    ++stats_.disconnects;
    ++sequence_;
    connected_ = false;
  }
  started_ = false;
  if (transport_.reconnect(config_.reconnect_timeout_ms)) {
    ++stats_.reconnects;
    connected_ = true;
    start();
  }
  return StreamStatus::fault;
}

StreamStatus SeekSource::stream_frame(fw::LineSink& sink) {
  if (!started_) {
    const TransferStatus s = start();
    if (s == TransferStatus::disconnected) return device_gone();
    if (s != TransferStatus::ok) {
      ++stats_.corrupt_transfers;  // the camera refused its start-up: no frame this call
      return StreamStatus::fault;
    }
  }
  for (std::uint32_t n = 0; n < config_.max_frames_without_image; ++n) {
    std::int64_t arrival_ns = 0;
    const Read r = read_frame(arrival_ns);
    if (r == Read::gone) return device_gone();
    if (r == Read::waiting) return StreamStatus::fault;  // counted; the frame may still come
    if (r == Read::lost) {
      ++sequence_;
      check_alignment_ = true;
      return StreamStatus::fault;
    }
    SeekFrameInfo info;
    parser_.parse_received(info);
    const bool check = check_alignment_;
    check_alignment_ = false;
    if (check && !starts_a_frame(info)) return resynchronise();
    const bool duplicate = follow_counter(info);
    switch (info.kind) {
      case SeekFrameKind::image: break;
      case SeekFrameKind::shutter:
        ++counters_.shutter_frames;
        ffc_pending_ = true;
        continue;
      case SeekFrameKind::startup: ++counters_.startup_frames; continue;
      default: ++counters_.calibration_frames; continue;
    }
    fw::FrameHeader header;
    header.width = parser_.model().width;
    header.height = parser_.model().image_height();
    header.sequence = sequence_++;
    header.sequence_valid = true;
    header.timestamp_ns = arrival_ns;
    header.timestamp_valid = arrival_ns != 0;
    if (duplicate) ++stats_.duplicates;  // delivered all the same, as the FLIR ONE's are
    header.ffc = ffc_pending_ ? fw::FfcState::completed : fw::FfcState::none;
    ffc_pending_ = false;
    sink.begin_frame(header);
    // The image rows lie one after another in the parser's frame: one run.
    sink.push_lines(0, header.height, parser_.image_row(0).data(), header.width, header.width);
    sink.end_frame();
    ++stats_.frames_delivered;
    return StreamStatus::frame;
  }
  ++stats_.corrupt_transfers;  // a device that never sends an image is not delivering frames
  return StreamStatus::fault;
}

}  // namespace bolo::hal
