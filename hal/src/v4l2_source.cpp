#include "bolo/hal/v4l2_source.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <thread>

#include "bolo/hal/y16_frame.hpp"

#include "xioctl.hpp"

namespace bolo::hal {
namespace {

// The sizes a node offers in `pixels`; empty when it does not offer the format at all.
V4l2Sizes format_sizes(int fd, V4l2Pixels pixels) {
  V4l2Sizes sizes;
  const std::uint32_t fourcc = v4l2_pixels_fourcc(pixels);
  bool offered = false;
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; xioctl(fd, VIDIOC_ENUM_FMT, &desc) == 0; ++desc.index)
    offered = offered || desc.pixelformat == fourcc;
  if (!offered) return sizes;
  v4l2_frmsizeenum size{};
  size.pixel_format = fourcc;
  for (size.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMESIZES, &size) == 0; ++size.index) {
    if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
      sizes.emplace_back(size.discrete.width, size.discrete.height);
    } else {
      sizes.emplace_back(size.stepwise.max_width, size.stepwise.max_height);
      break;
    }
  }
  if (sizes.empty()) sizes.emplace_back(0, 0);  // offered without size enumeration: take S_FMT's answer
  return sizes;
}

// What this node can do: drivers with several nodes per device report the node's own
// capabilities apart from the whole device's.
std::uint32_t node_capabilities(const v4l2_capability& cap) {
  return (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
}

}  // namespace

const char* v4l2_pixels_name(V4l2Pixels pixels) {
  switch (pixels) {
    case V4l2Pixels::y16: return "Y16";
    case V4l2Pixels::grey: return "GREY";
    case V4l2Pixels::yuyv: return "YUYV";
    case V4l2Pixels::uyvy: return "UYVY";
  }
  return "?";
}

std::optional<V4l2Pixels> v4l2_pixels_named(std::string_view name) {
  for (V4l2Pixels p : kV4l2PixelOrder) {
    const std::string_view known = v4l2_pixels_name(p);
    if (known.size() == name.size() &&
        std::equal(known.begin(), known.end(), name.begin(), [](char a, char b) {
          return a == std::toupper(static_cast<unsigned char>(b));
        }))
      return p;
  }
  return std::nullopt;
}

std::uint32_t v4l2_pixels_fourcc(V4l2Pixels pixels) {
  switch (pixels) {
    case V4l2Pixels::y16: return V4L2_PIX_FMT_Y16;
    case V4l2Pixels::grey: return V4L2_PIX_FMT_GREY;
    case V4l2Pixels::yuyv: return V4L2_PIX_FMT_YUYV;
    case V4l2Pixels::uyvy: return V4L2_PIX_FMT_UYVY;
  }
  return 0;
}

V4l2Sizes V4l2DeviceEntry::sizes(V4l2Pixels pixels) const {
  for (const Format& f : formats)
    if (f.pixels == pixels) return f.sizes;
  return {};
}

std::optional<std::pair<std::uint32_t, std::uint32_t>> choose_frame_size(const V4l2Sizes& sizes,
                                                                        const V4l2Config& c, V4l2Pixels pixels) {
  // The largest size that fits the request; with automatic telemetry that is the Lepton's
  // 160x122 over its 160x120 (80x63 over 80x60). Unasked, only sizes up to max_auto_pixels count
  // (thermal cores are far below it; a test pattern generator's 16k modes would not fit a board's
  // memory); when none is that small, the smallest. Telemetry rows come only with Y16.
  std::optional<std::pair<std::uint32_t, std::uint32_t>> pick;
  for (auto [w, h] : sizes) {
    if (w == 0 || h == 0) continue;
    const std::uint32_t tel_rows = pixels == V4l2Pixels::y16 ? lepton_telemetry_rows(w, h) : 0;
    const bool tel = tel_rows > 0;
    const std::uint32_t image_h = h - tel_rows;
    if (c.telemetry == TelemetryRows::on && !tel) continue;
    if (c.telemetry == TelemetryRows::off && tel) continue;
    if (c.width != 0 && (w != c.width || image_h != c.height)) continue;
    const std::uint64_t area = std::uint64_t{w} * h;
    if (!pick) {
      pick = {w, h};
      continue;
    }
    const std::uint64_t best = std::uint64_t{pick->first} * pick->second;
    const bool fits = c.width != 0 || area <= c.max_auto_pixels;
    const bool best_fits = c.width != 0 || best <= c.max_auto_pixels;
    if ((fits && (!best_fits || area > best)) || (!fits && !best_fits && area < best)) pick = {w, h};
  }
  return pick;
}

struct V4l2Source::Device {
  int fd = -1;
  struct Buffer {
    void* start = MAP_FAILED;
    std::size_t length = 0;
  };
  std::vector<Buffer> buffers;
  bool streaming = false;

  ~Device() { close(); }
  void close() {
    if (fd < 0) return;
    if (streaming) {
      v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      xioctl(fd, VIDIOC_STREAMOFF, &type);
    }
    for (Buffer& b : buffers)
      if (b.start != MAP_FAILED) ::munmap(b.start, b.length);
    buffers.clear();
    ::close(fd);
    fd = -1;
    streaming = false;
  }

  // Opens, negotiates and starts streaming; returns an error message, empty on success.
  std::string open(const V4l2Config& c, V4l2Negotiated& n) {
    fd = ::open(c.path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return std::string("cannot open: ") + std::strerror(errno);
    v4l2_capability cap{};
    if (xioctl(fd, VIDIOC_QUERYCAP, &cap) != 0) return "not a V4L2 device";
    const std::uint32_t caps = node_capabilities(cap);
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) return "not a video capture device";
    if (!(caps & V4L2_CAP_STREAMING)) return "does not support streaming I/O";
    n.driver = reinterpret_cast<const char*>(cap.driver);
    n.card = reinterpret_cast<const char*>(cap.card);

    // The forced format, else the first of kV4l2PixelOrder offered.
    V4l2Pixels pixels = c.pixels.value_or(V4l2Pixels::y16);
    V4l2Sizes sizes;
    for (V4l2Pixels p : kV4l2PixelOrder) {
      if (c.pixels && p != *c.pixels) continue;
      sizes = format_sizes(fd, p);
      pixels = p;
      if (!sizes.empty()) break;
    }
    if (sizes.empty())
      return c.pixels ? std::string("does not offer ") + v4l2_pixels_name(pixels)
                      : "offers none of Y16, GREY, YUYV, UYVY (see `bolo devices`)";
    const bool enumerated = !(sizes.size() == 1 && sizes[0].first == 0);
    const auto chosen = choose_frame_size(sizes, c, pixels);
    const std::pair<std::uint32_t, std::uint32_t> pick = chosen.value_or(std::pair<std::uint32_t, std::uint32_t>{0, 0});
    if (enumerated && !chosen)
      return std::string("no ") + v4l2_pixels_name(pixels) + " size matches the request (see `bolo devices`)";

    v4l2_format fmt{};
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    fmt.fmt.pix.pixelformat = v4l2_pixels_fourcc(pixels);
    fmt.fmt.pix.width = pick.first != 0 ? pick.first : c.width;
    fmt.fmt.pix.height = pick.second != 0 ? pick.second : c.height;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (xioctl(fd, VIDIOC_S_FMT, &fmt) != 0) return std::string("VIDIOC_S_FMT: ") + std::strerror(errno);
    if (fmt.fmt.pix.pixelformat != v4l2_pixels_fourcc(pixels))
      return std::string("the driver refused ") + v4l2_pixels_name(pixels);
    const std::uint32_t tel_rows = pixels == V4l2Pixels::y16 && c.telemetry != TelemetryRows::off
                                       ? lepton_telemetry_rows(fmt.fmt.pix.width, fmt.fmt.pix.height)
                                       : 0;
    n.pixels = pixels;
    n.width = fmt.fmt.pix.width;
    n.telemetry_rows = tel_rows;
    n.image_rows = fmt.fmt.pix.height - n.telemetry_rows;
    n.bytes_per_line = fmt.fmt.pix.bytesperline;
    if (n.width == 0 || n.image_rows == 0) return "the driver reported an empty frame size";

    v4l2_streamparm parm{};
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd, VIDIOC_G_PARM, &parm) == 0 && parm.parm.capture.timeperframe.denominator != 0)
      n.frame_period_ns = static_cast<std::uint32_t>(1'000'000'000ull * parm.parm.capture.timeperframe.numerator /
                                                     parm.parm.capture.timeperframe.denominator);

    v4l2_requestbuffers req{};
    req.count = c.buffers < 2 ? 2 : c.buffers;
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd, VIDIOC_REQBUFS, &req) != 0 || req.count < 2)
      return std::string("VIDIOC_REQBUFS (mmap): ") + std::strerror(errno);
    for (std::uint32_t i = 0; i < req.count; ++i) {
      v4l2_buffer buf{};
      buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buf.memory = V4L2_MEMORY_MMAP;
      buf.index = i;
      if (xioctl(fd, VIDIOC_QUERYBUF, &buf) != 0) return std::string("VIDIOC_QUERYBUF: ") + std::strerror(errno);
      Buffer b;
      b.length = buf.length;
      b.start = ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, buf.m.offset);
      if (b.start == MAP_FAILED) return std::string("mmap: ") + std::strerror(errno);
      buffers.push_back(b);
      if (xioctl(fd, VIDIOC_QBUF, &buf) != 0) return std::string("VIDIOC_QBUF: ") + std::strerror(errno);
    }
    n.buffers = req.count;
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd, VIDIOC_STREAMON, &type) != 0) return std::string("VIDIOC_STREAMON: ") + std::strerror(errno);
    streaming = true;
    return {};
  }
};

namespace {

// A dequeued buffer as the driver filled it.
V4l2BufferStream::Buffer filled(const v4l2_buffer& buf, const V4l2Source::Device::Buffer& mem) {
  V4l2BufferStream::Buffer b;
  b.bytes = {static_cast<const std::uint8_t*>(mem.start), std::min<std::size_t>(buf.bytesused, mem.length)};
  b.sequence = buf.sequence;
  b.error = (buf.flags & V4L2_BUF_FLAG_ERROR) != 0;
  b.timestamp_monotonic = (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
  b.timestamp_ns = std::int64_t{buf.timestamp.tv_sec} * 1'000'000'000 + std::int64_t{buf.timestamp.tv_usec} * 1000;
  return b;
}

}  // namespace

bool SequenceGaps::add(std::uint32_t sequence) {
  if (!have_) {
    have_ = true;
    highest_ = sequence;
    return true;
  }
  const auto step = static_cast<std::int32_t>(sequence - highest_);
  if (step > 0) {
    missing_ += static_cast<std::uint32_t>(step - 1);
    highest_ = sequence;
    return true;
  }
  ++late_;
  if (missing_ > 0) --missing_;
  return false;
}

V4l2BufferStream::V4l2BufferStream(const Y16Layout& layout) : layout_(layout), line_(layout.width) {}

void V4l2BufferStream::reopened(const Y16Layout& layout) {
  layout_ = layout;
  line_.resize(layout.width);
  sequence_offset_ = last_sequence_ + 2;  // a gap: the driver starts again at 0
  gaps_.restart();
  ffc_.restart();
  counter_.restart();  // the camera may have restarted too
  have_counted_sequence_ = false;
}

// Every number the driver skipped is a frame that never arrived (unless it comes late).
void V4l2BufferStream::follow_sequence(std::uint32_t sequence, SourceStats& stats) {
  const std::uint64_t missing_before = gaps_.missing();
  gaps_.add(sequence);
  stats.dropped = stats.dropped - missing_before + gaps_.missing();
  last_sequence_ = sequence_offset_ + sequence;
}

fw::FrameHeader V4l2BufferStream::header_of(const Buffer& buffer) const {
  fw::FrameHeader header;
  header.width = layout_.width;
  header.height = layout_.image_rows;
  header.sequence = last_sequence_;
  header.sequence_valid = true;
  header.timestamp_valid = buffer.timestamp_monotonic;
  header.timestamp_ns = buffer.timestamp_ns;
  header.ffc = fw::FfcState::unknown;
  return header;
}

// From the telemetry just read: the FFC state (LeptonFfcTracker), FPA and housing temperature.
void V4l2BufferStream::telemetry_to_header(fw::FrameHeader& header) {
  header.ffc = ffc_.next(telemetry_);
  header.fpa_temp_mc = centikelvin_to_mc(telemetry_.fpa_temp_ck);
  header.housing_temp_mc = centikelvin_to_mc(telemetry_.housing_temp_ck);
}

// A counter step over n frames while the driver's numbers advanced by s since the previous frame
// with telemetry: s - 1 frames are the driver's to count (dropped, or handed over broken); the
// other n - s never reached it, so the camera skipped them (or the wire lost them unnoticed).
// The driver's numbers already leave a gap for its s - 1; the delivered sequence moves up by the
// others, from this frame on, so that they leave one too. Only a forward step past a newer driver
// number can: a repeat, a late frame or a jump adds nothing.
void V4l2BufferStream::follow_frame_counter(std::uint32_t sequence, SourceStats& stats) {
  const LeptonFrameCounter::Step step = counter_.add(telemetry_.frame_counter);
  const auto numbered = static_cast<std::int32_t>(sequence - counted_sequence_);
  const bool newer = !have_counted_sequence_ || numbered > 0;
  if (step == LeptonFrameCounter::Step::repeat) ++stats.duplicates;
  if (step == LeptonFrameCounter::Step::forward && have_counted_sequence_ && numbered > 0) {
    const std::uint32_t skipped = counter_.skipped_beyond(static_cast<std::uint32_t>(numbered) - 1u);
    skipped_in_camera_ += skipped;
    sequence_offset_ += skipped;
    last_sequence_ += skipped;
  }
  if (newer) {
    have_counted_sequence_ = true;
    counted_sequence_ = sequence;
  }
}

void V4l2BufferStream::push_image(const Y16Frame& frame, const fw::FrameHeader& header, fw::LineSink& sink) {
  sink.begin_frame(header);
  for (std::uint32_t row = 0; row < layout_.image_rows; ++row) {
    frame.image_row(row, line_);
    sink.push_line(row, fw::LineView(line_.data(), line_.size()));
  }
  sink.end_frame();
}

StreamStatus V4l2BufferStream::deliver(const Buffer& buffer, fw::LineSink& sink, SourceStats& stats) {
  follow_sequence(buffer.sequence, stats);
  if (buffer.error) {
    ++stats.corrupt_transfers;
    return StreamStatus::fault;
  }
  switch (Y16Frame::check(buffer.bytes, layout_)) {
    case Y16Check::ok: break;
    case Y16Check::short_frame: ++stats.short_transfers; return StreamStatus::fault;
    case Y16Check::bad_layout: ++stats.corrupt_transfers; return StreamStatus::fault;
  }
  const Y16Frame frame(buffer.bytes, layout_);
  const bool has_telemetry = frame.telemetry(telemetry_);
  // The counter before the header: frames the camera skipped move this frame's sequence up.
  if (has_telemetry) follow_frame_counter(buffer.sequence, stats);
  fw::FrameHeader header = header_of(buffer);
  if (has_telemetry) telemetry_to_header(header);
  push_image(frame, header, sink);
  ++stats.frames_delivered;
  return StreamStatus::frame;
}

V4l2Source::V4l2Source(const V4l2Config& config) : config_(config), device_(std::make_unique<Device>()) {
  const std::string why = device_->open(config_, negotiated_);
  if (!why.empty()) throw std::runtime_error(config_.path + ": " + why);
  buffers_.emplace(layout());
}

V4l2Source::~V4l2Source() = default;

Y16Layout V4l2Source::layout() const {
  return {negotiated_.width, negotiated_.image_rows, negotiated_.telemetry_rows, negotiated_.bytes_per_line,
          negotiated_.pixels};
}

SourceFormat V4l2Source::format() const {
  SourceFormat f;
  f.width = negotiated_.width;
  f.height = negotiated_.image_rows;
  if (tone_mapped(negotiated_.pixels)) {
    f.bits = 8;
    f.units = PixelUnits::counts8;
  } else {
    f.bits = negotiated_.telemetry_rows > 0 ? 14 : 16;  // Lepton Y16: raw 14-bit counts
  }
  f.frame_period_ns = negotiated_.frame_period_ns;
  return f;
}

ExtraCounters V4l2Source::extra_counters() const {
  ExtraCounters c;
  c.add("out_of_order", out_of_order());
  c.add("skipped_in_camera", skipped_in_camera());
  c.add("counter_jumps", counter_jumps());
  return c;
}

StreamStatus V4l2Source::lost_device() {
  if (device_->fd >= 0) {  // counted once per unplug, however long the camera stays away
    ++stats_.disconnects;
    device_->close();
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(config_.reconnect_timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    V4l2Negotiated again;
    if (device_->open(config_, again).empty() && again.width == negotiated_.width &&
        again.image_rows == negotiated_.image_rows && again.pixels == negotiated_.pixels) {
      negotiated_ = again;
      buffers_->reopened(layout());
      ++stats_.reconnects;
      return StreamStatus::fault;
    }
    device_->close();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return StreamStatus::fault;
}

StreamStatus V4l2Source::stream_frame(fw::LineSink& sink) {
  if (device_->fd < 0) return lost_device();
  pollfd p{device_->fd, POLLIN, 0};
  const int ready = ::poll(&p, 1, static_cast<int>(config_.timeout_ms));
  if (ready == 0) {
    ++stats_.timeouts;
    return StreamStatus::fault;
  }
  if (ready < 0) {
    if (errno == EINTR) return StreamStatus::fault;
    return lost_device();
  }
  if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) return lost_device();

  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(device_->fd, VIDIOC_DQBUF, &buf) != 0) {
    if (errno == EAGAIN) {
      ++stats_.timeouts;
      return StreamStatus::fault;
    }
    if (errno == ENODEV) return lost_device();
    // EIO: the driver dequeued a buffer it could not fill; give it back and go on.
    ++stats_.corrupt_transfers;
    if (errno == EIO && buf.index < device_->buffers.size()) xioctl(device_->fd, VIDIOC_QBUF, &buf);
    return StreamStatus::fault;
  }
  struct Requeue {
    Device& d;
    v4l2_buffer& b;
    ~Requeue() { xioctl(d.fd, VIDIOC_QBUF, &b); }
  } requeue{*device_, buf};
  if (buf.index >= device_->buffers.size()) {
    ++stats_.corrupt_transfers;
    return StreamStatus::fault;
  }
  return buffers_->deliver(filled(buf, device_->buffers[buf.index]), sink, stats_);
}

std::vector<V4l2DeviceEntry> list_v4l2_devices() {
  std::vector<V4l2DeviceEntry> out;
  std::error_code ec;
  std::vector<std::string> nodes;
  for (const auto& e : std::filesystem::directory_iterator("/dev", ec))
    if (e.path().filename().string().rfind("video", 0) == 0) nodes.push_back(e.path().string());
  std::sort(nodes.begin(), nodes.end());
  for (const std::string& node : nodes) {
    const int fd = ::open(node.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    v4l2_capability cap{};
    if (xioctl(fd, VIDIOC_QUERYCAP, &cap) == 0 && (node_capabilities(cap) & V4L2_CAP_VIDEO_CAPTURE)) {
      V4l2DeviceEntry entry{node, reinterpret_cast<const char*>(cap.card), reinterpret_cast<const char*>(cap.driver), {}};
      for (V4l2Pixels p : kV4l2PixelOrder) {
        V4l2Sizes sizes = format_sizes(fd, p);
        if (!sizes.empty()) entry.formats.push_back({p, std::move(sizes)});
      }
      if (!entry.formats.empty()) out.push_back(std::move(entry));
    }
    ::close(fd);
  }
  return out;
}

}  // namespace bolo::hal
