#pragma once
// ioctl(2) retried while a signal interrupts it: the V4L2 and UVC control paths' one call.

#include <sys/ioctl.h>

#include <cerrno>

namespace bolo::hal {

inline int xioctl(int fd, unsigned long request, void* arg) {
  int rc;
  do rc = ::ioctl(fd, request, arg);
  while (rc == -1 && errno == EINTR);
  return rc;
}

}  // namespace bolo::hal
