#include "bolo/hal/seek_source.hpp"

namespace bolo::hal {
namespace {

bool ok(const Transfer& t) { return t.status == TransferStatus::ok; }

}  // namespace

SeekSource::SeekSource(VendorUsbTransport& transport, const SeekModel& model, const SeekSourceConfig& config)
    : transport_(transport),
      config_(config),
      parser_(model),
      startup_(model),
      corrector_(model),
      chunk_(model.chunk_bytes) {}

SeekSource::~SeekSource() {
  if (started_) close_camera();
}

SourceFormat SeekSource::format() const {
  SourceFormat f;
  f.width = corrector_.crop().width;
  f.height = corrector_.crop().height;
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
  c.add("images_before_shutter", counters_.images_before_shutter);
  c.add("counter_jumps", counters_.counter_jumps);
  c.add("dead_pixels", corrector_.dead_pixels());
  return c;
}

void SeekSource::close_camera() {
  for (int i = 0; i < kSeekCloseRepeats; ++i) transport_.control_out(seek::kSetOperationMode, kSeekIdleMode);
}

TransferStatus SeekSource::send(const SeekControlStep& step) {
  if (!step.read) return transport_.control_out(step.request, step.data()).status;
  std::span<std::uint8_t> into{reply_, step.length};
  if (step.request == seek::kGetFirmwareInfo && step.length == sizeof firmware_) into = firmware_;
  if (step.request == seek::kReadChipId && step.length == sizeof chip_id_) into = chip_id_;
  return transport_.control_in(step.request, into).status;
}

// TARGET_PLATFORM; if refused, the close sequence and TARGET_PLATFORM once more; then the rest,
// stopping at the first step that fails (as the driver does).
TransferStatus SeekSource::send_startup_sequence() {
  const std::span<const SeekControlStep> steps = startup_.steps();
  TransferStatus s = send(steps[0]);
  if (s != TransferStatus::ok && s != TransferStatus::disconnected) {
    close_camera();
    s = send(steps[0]);
  }
  for (std::size_t i = 1; i < steps.size() && s == TransferStatus::ok; ++i) s = send(steps[i]);
  return s;
}

// Open as the driver does: the sequence, then the first frame must be the start-up frame (its
// dead pixels are taken); a frame that does not arrive runs the sequence again, up to
// kSeekStartAttempts in all. ok, disconnected, error (a step refused, another first frame) or
// timeout (no start-up frame in any attempt).
TransferStatus SeekSource::start() {
  corrector_.reset();
  have_counter_ = false;  // a camera that starts counts afresh
  check_alignment_ = false;
  for (int attempt = 0; attempt < kSeekStartAttempts; ++attempt) {
    const TransferStatus sent = send_startup_sequence();
    if (sent != TransferStatus::ok) {
      if (sent != TransferStatus::disconnected) ++counters_.start_failures;
      return sent;
    }
    frame_requested_ = false;
    std::int64_t arrival_ns = 0;
    Read r = Read::waiting;
    while (r == Read::waiting) r = read_frame(arrival_ns);
    if (r == Read::gone) return TransferStatus::disconnected;
    if (r == Read::lost) {
      if (!drain()) return TransferStatus::disconnected;
      continue;
    }
    SeekFrameInfo info;
    parser_.parse_received(info);
    if (info.kind != SeekFrameKind::startup) {
      ++counters_.start_failures;
      return TransferStatus::error;
    }
    follow_counter(info);
    ++counters_.startup_frames;
    corrector_.take_startup(parser_.words());
    started_ = true;
    return TransferStatus::ok;
  }
  ++counters_.start_failures;
  return TransferStatus::timeout;
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
  return drain() ? StreamStatus::fault : device_gone();
}

// Reads and drops what the camera still sends until it is silent (bounded: two frames' worth).
// False when the device went away meanwhile.
bool SeekSource::drain() {
  const std::size_t chunks_per_frame = (parser_.model().frame_bytes() + chunk_.size() - 1) / chunk_.size();
  for (std::size_t n = 0; n < 2 * chunks_per_frame; ++n) {
    const Transfer t = transport_.next(chunk_, config_.transfer_timeout_ms);
    if (t.status == TransferStatus::disconnected) return false;
    if (t.status != TransferStatus::ok) break;  // silent (the wait was the point, not a fault)
  }
  return true;
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
      // A refused step or a wrong first frame; a camera that sent nothing cost its timeouts.
      if (s == TransferStatus::error) ++stats_.corrupt_transfers;
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
        corrector_.take_shutter(parser_.words());
        continue;
      // Only the one at the open gives the dead pixels (as in the driver).
      case SeekFrameKind::startup: ++counters_.startup_frames; continue;
      default: ++counters_.calibration_frames; continue;
    }
    if (config_.subtract_shutter && !corrector_.has_shutter()) {
      ++counters_.images_before_shutter;  // the driver too reads on until it has a shutter frame
      continue;
    }
    corrector_.correct(parser_.words(), config_.subtract_shutter);
    fw::FrameHeader header;
    header.width = corrector_.crop().width;
    header.height = corrector_.crop().height;
    header.sequence = sequence_++;
    header.sequence_valid = true;
    header.timestamp_ns = arrival_ns;
    header.timestamp_valid = arrival_ns != 0;
    if (duplicate) ++stats_.duplicates;  // delivered all the same, as the FLIR ONE's are
    header.ffc = ffc_pending_ ? fw::FfcState::completed : fw::FfcState::none;
    ffc_pending_ = false;
    sink.begin_frame(header);
    sink.push_lines(0, header.height, corrector_.image().data(), header.width, header.width);
    sink.end_frame();
    ++stats_.frames_delivered;
    return StreamStatus::frame;
  }
  ++stats_.corrupt_transfers;  // a device that never sends an image is not delivering frames
  return StreamStatus::fault;
}

}  // namespace bolo::hal
