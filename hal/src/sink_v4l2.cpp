// v4l2:/dev/videoN: the frames to a V4L2 output device (a v4l2loopback node), which other programs
// then open as a Y16 camera (GStreamer's GRAY16_LE). VIDIOC_S_FMT on the output queue with
// V4L2_PIX_FMT_Y16 at the frames' size, then one write() per frame.

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "bolo/hal/frame_sink.hpp"
#include "builtin_sinks.hpp"

namespace bolo::hal::detail {
namespace {

int retried_ioctl(int fd, unsigned long request, void* arg) {
  int rc = 0;
  do rc = ::ioctl(fd, request, arg);
  while (rc == -1 && errno == EINTR);
  return rc;
}

std::string fourcc_text(std::uint32_t f) {
  std::string text;
  for (int i = 0; i < 4; ++i) text += static_cast<char>((f >> (8 * i)) & 0xFF);
  return text;
}

std::string size_text(std::uint32_t width, std::uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// Closes the node however the sink's constructor ends.
struct OwnedFd {
  int fd = -1;
  OwnedFd() = default;
  OwnedFd(const OwnedFd&) = delete;
  OwnedFd& operator=(const OwnedFd&) = delete;
  ~OwnedFd() {
    if (fd >= 0) ::close(fd);
  }
};

class V4l2OutputSink final : public FrameSink {
 public:
  V4l2OutputSink(std::string spec, const std::string& node, std::uint32_t width, std::uint32_t height)
      : spec_(std::move(spec)), width_(width), height_(height) {
    const auto refuse = [&](const std::string& why) { throw SinkError(spec_ + ": " + node + ": " + why); };
    fd_.fd = ::open(node.c_str(), O_RDWR | O_CLOEXEC);
    if (fd_.fd < 0) refuse(std::string("cannot open: ") + std::strerror(errno));
    v4l2_capability cap{};
    if (retried_ioctl(fd_.fd, VIDIOC_QUERYCAP, &cap) != 0) refuse("not a V4L2 device");
    const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
    const std::string card = reinterpret_cast<const char*>(cap.card);
    const std::string driver = reinterpret_cast<const char*>(cap.driver);
    if ((caps & V4L2_CAP_VIDEO_OUTPUT) == 0)
      refuse("not a video output device ('" + card + "', driver " + driver +
             "; a v4l2loopback node is one: modprobe v4l2loopback)");
    if ((caps & V4L2_CAP_READWRITE) == 0) refuse("does not take frames by write() ('" + card + "', driver " + driver + ")");
    v4l2_format format{};
    format.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    format.fmt.pix.width = width;
    format.fmt.pix.height = height;
    format.fmt.pix.pixelformat = V4L2_PIX_FMT_Y16;
    format.fmt.pix.field = V4L2_FIELD_NONE;
    format.fmt.pix.bytesperline = width * 2;
    format.fmt.pix.sizeimage = width * height * 2;
    const std::string wanted = "Y16 " + size_text(width, height) + " output";
    if (retried_ioctl(fd_.fd, VIDIOC_S_FMT, &format) != 0)
      refuse("refuses " + wanted + " (VIDIOC_S_FMT: " + std::strerror(errno) + ")");
    const v4l2_pix_format& pix = format.fmt.pix;
    if (pix.pixelformat != V4L2_PIX_FMT_Y16 || pix.width != width || pix.height != height ||
        (pix.bytesperline != 0 && pix.bytesperline < width * 2))
      refuse("refuses " + wanted + " (it set " + fourcc_text(pix.pixelformat) + " " + size_text(pix.width, pix.height) +
             ")");
    bytes_per_line_ = std::max<std::size_t>(pix.bytesperline, std::size_t{width} * 2);
    if (bytes_per_line_ != std::size_t{width} * 2) padded_.resize(bytes_per_line_ * height);
  }
  // One write() is one frame to a V4L2 output device: a short one is refused, not continued.
  void write(std::span<const std::uint16_t> frame, const rec::FrameRow&) override {
    const void* data = frame.data();
    std::size_t bytes = frame.size_bytes();
    if (!padded_.empty()) {
      for (std::uint32_t y = 0; y < height_; ++y)
        std::memcpy(padded_.data() + y * bytes_per_line_, frame.data() + std::size_t{y} * width_, std::size_t{width_} * 2);
      data = padded_.data();
      bytes = padded_.size();
    }
    ssize_t written = 0;
    do written = ::write(fd_.fd, data, bytes);
    while (written < 0 && errno == EINTR);
    if (written < 0) throw SinkError(spec_ + ": write: " + std::strerror(errno));
    if (static_cast<std::size_t>(written) != bytes)
      throw SinkError(spec_ + ": write: the device took " + std::to_string(written) + " of a frame's " +
                      std::to_string(bytes) + " bytes");
  }
  void finish() override {}

 private:
  std::string spec_;
  std::uint32_t width_, height_;
  OwnedFd fd_;
  std::size_t bytes_per_line_ = 0;
  std::vector<std::uint8_t> padded_;  // rows at the driver's bytesperline, when it pads them
};

}  // namespace

SinkBackend v4l2_sink() {
  SinkBackend b;
  b.scheme = "v4l2";
  b.argument = "/dev/videoN";
  b.argument_help = "a V4L2 output device node, e.g. v4l2:/dev/video10";
  b.summary = "a V4L2 output device (v4l2loopback), Y16 (GStreamer GRAY16_LE), one write() per frame";
  b.open = [](const std::string& spec, const std::string& node, const SinkSetup& setup) {
    return std::make_unique<V4l2OutputSink>(spec, node, setup.info.width, setup.info.height);
  };
  return b;
}

}  // namespace bolo::hal::detail
