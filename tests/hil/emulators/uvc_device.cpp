#include "uvc_device.hpp"

#include <fcntl.h>
#include <linux/usb/g_uvc.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/select.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace bolo::hil::uvc {

namespace {

// usb_f_uvc answers VIDIOC_REQBUFS with the buffer count (a positive return): only < 0 fails.
int xioctl(int fd, unsigned long request, void* arg) {
  int rc;
  do rc = ::ioctl(fd, request, arg);
  while (rc == -1 && errno == EINTR);
  return rc;
}

}  // namespace

UvcDevice::UvcDevice(std::string node) : node_(std::move(node)) {
  fd_ = ::open(node_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error(node_ + ": " + std::strerror(errno));
  for (std::uint32_t type : {UVC_EVENT_CONNECT, UVC_EVENT_DISCONNECT, UVC_EVENT_STREAMON, UVC_EVENT_STREAMOFF,
                             UVC_EVENT_DATA, UVC_EVENT_SETUP}) {
    v4l2_event_subscription sub{};
    sub.type = type;
    if (xioctl(fd_, VIDIOC_SUBSCRIBE_EVENT, &sub) < 0) {
      const int saved = errno;
      ::close(fd_);
      throw std::runtime_error(node_ + ": VIDIOC_SUBSCRIBE_EVENT: " + std::strerror(saved));
    }
  }
}

UvcDevice::~UvcDevice() {
  try {
    stop();
  } catch (const std::exception&) {
    // Closing releases the buffers and the function anyway.
  }
  ::close(fd_);  // usb_f_uvc disconnects from the host when its last event subscriber leaves
}

bool UvcDevice::wait(int timeout_ms) {
  // select(): events are "exceptional"; written buffers come back as "writable". (poll() on a
  // queue that is not streaming reports POLLERR at once, which would spin.)
  fd_set except, write;
  FD_ZERO(&except);
  FD_ZERO(&write);
  FD_SET(fd_, &except);
  if (streaming_) FD_SET(fd_, &write);
  timeval tv{timeout_ms / 1000, (timeout_ms % 1000) * 1000};
  const int n = ::select(fd_ + 1, nullptr, streaming_ ? &write : nullptr, &except, &tv);
  if (n < 0 && errno != EINTR) throw std::runtime_error(node_ + ": select: " + std::strerror(errno));
  return n > 0;
}

std::optional<Event> UvcDevice::next_event() {
  v4l2_event ev{};
  if (xioctl(fd_, VIDIOC_DQEVENT, &ev) < 0) {
    if (errno == ENOENT || errno == EAGAIN) return std::nullopt;
    throw std::runtime_error(node_ + ": VIDIOC_DQEVENT: " + std::strerror(errno));
  }
  const auto* uvc = reinterpret_cast<const uvc_event*>(&ev.u.data);
  Event out;
  switch (ev.type) {
    case UVC_EVENT_CONNECT: out.type = EventType::connect; break;
    case UVC_EVENT_DISCONNECT: out.type = EventType::disconnect; break;
    case UVC_EVENT_STREAMON: out.type = EventType::streamon; break;
    case UVC_EVENT_STREAMOFF: out.type = EventType::streamoff; break;
    case UVC_EVENT_SETUP:
      out.type = EventType::setup;
      out.setup = uvc->req;
      break;
    case UVC_EVENT_DATA: {
      out.type = EventType::data;
      const int length = uvc->data.length < 0 ? 0 : uvc->data.length;
      out.data.assign(uvc->data.data, uvc->data.data + std::min<int>(length, sizeof uvc->data.data));
      break;
    }
    default: return std::nullopt;
  }
  return out;
}

void UvcDevice::respond(const std::optional<std::vector<std::uint8_t>>& bytes) {
  uvc_request_data r{};
  if (!bytes) {
    r.length = -1;  // the function stalls ep0
  } else {
    r.length = static_cast<std::int32_t>(std::min(bytes->size(), sizeof r.data));
    std::memcpy(r.data, bytes->data(), static_cast<std::size_t>(r.length));
  }
  if (xioctl(fd_, UVCIOC_SEND_RESPONSE, &r) < 0)
    throw std::runtime_error(node_ + ": UVCIOC_SEND_RESPONSE: " + std::strerror(errno));
}

void UvcDevice::accept_out(std::uint16_t length) {
  uvc_request_data r{};
  r.length = length;
  if (xioctl(fd_, UVCIOC_SEND_RESPONSE, &r) < 0)
    throw std::runtime_error(node_ + ": UVCIOC_SEND_RESPONSE (OUT data stage): " + std::strerror(errno));
}

void UvcDevice::start(FrameSize size, std::uint32_t count) {
  stop();
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  fmt.fmt.pix.pixelformat = V4L2_PIX_FMT_Y16;
  fmt.fmt.pix.width = size.width;
  fmt.fmt.pix.height = size.height;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  fmt.fmt.pix.sizeimage = size.bytes();
  if (xioctl(fd_, VIDIOC_S_FMT, &fmt) < 0) throw std::runtime_error(node_ + ": VIDIOC_S_FMT: " + std::strerror(errno));
  if (fmt.fmt.pix.pixelformat != V4L2_PIX_FMT_Y16 || fmt.fmt.pix.width != size.width ||
      fmt.fmt.pix.height != size.height || fmt.fmt.pix.sizeimage != size.bytes())
    throw std::runtime_error(node_ + ": the function settled on another format than Y16 " +
                             std::to_string(size.width) + "x" + std::to_string(size.height));
  v4l2_requestbuffers req{};
  req.count = count;
  req.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &req) < 0 || req.count < 2)
    throw std::runtime_error(node_ + ": VIDIOC_REQBUFS: " + std::strerror(errno));
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &buf) < 0)
      throw std::runtime_error(node_ + ": VIDIOC_QUERYBUF: " + std::strerror(errno));
    void* p = ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
    if (p == MAP_FAILED) throw std::runtime_error(node_ + ": mmap: " + std::strerror(errno));
    buffers_.push_back({p, buf.length});
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) < 0)
    throw std::runtime_error(node_ + ": VIDIOC_STREAMON: " + std::strerror(errno));
  streaming_ = true;
}

void UvcDevice::stop() {
  if (streaming_) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);
    streaming_ = false;
  }
  for (Buffer& b : buffers_) ::munmap(b.start, b.length);
  if (!buffers_.empty()) {
    buffers_.clear();
    v4l2_requestbuffers req{};
    req.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    req.memory = V4L2_MEMORY_MMAP;
    xioctl(fd_, VIDIOC_REQBUFS, &req);  // count 0: free them
  }
}

std::optional<std::uint32_t> UvcDevice::take_done() {
  if (!streaming_) return std::nullopt;
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &buf) < 0) {
    if (errno == EAGAIN) return std::nullopt;
    throw std::runtime_error(node_ + ": VIDIOC_DQBUF: " + std::strerror(errno));
  }
  return buf.index;
}

void UvcDevice::queue(std::uint32_t index, std::span<const std::uint8_t> bytes) {
  if (index >= buffers_.size() || bytes.size() > buffers_[index].length)
    throw std::runtime_error(node_ + ": frame of " + std::to_string(bytes.size()) + " bytes does not fit buffer " +
                             std::to_string(index));
  std::memcpy(buffers_[index].start, bytes.data(), bytes.size());
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
  buf.memory = V4L2_MEMORY_MMAP;
  buf.index = index;
  buf.bytesused = static_cast<std::uint32_t>(bytes.size());
  buf.field = V4L2_FIELD_NONE;
  if (xioctl(fd_, VIDIOC_QBUF, &buf) < 0) throw std::runtime_error(node_ + ": VIDIOC_QBUF: " + std::strerror(errno));
}

}  // namespace bolo::hil::uvc
