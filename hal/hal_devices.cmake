# bolo_hal_devices: the I/O layers under the protocol parsers. libusb-1.0 and libgpiod are
# optional: a cross build finds no target packages (pkg-config would hand it the host's), so
# they are only looked for natively or when the caller points PKG_CONFIG_LIBDIR at a sysroot.
bolo_add_library(hal_devices HEADERS NONE NO_INSTALL SOURCES
  src/captured_transfers.cpp
  src/v4l2_source.cpp
  src/uvc_controls.cpp
  src/gpio_lines.cpp
  src/device_spec.cpp)
target_link_libraries(bolo_hal_devices PUBLIC bolo_hal_protocols)

option(BOLO_WITH_LIBUSB "USB backends (FLIR ONE, Seek) through libusb-1.0 when found" ON)
option(BOLO_WITH_LIBGPIOD "GPIO backend through libgpiod when found" ON)
set(BOLO_HAVE_LIBUSB OFF)
set(BOLO_HAVE_LIBGPIOD OFF)
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND AND (NOT CMAKE_CROSSCOMPILING OR DEFINED ENV{PKG_CONFIG_LIBDIR}))
  if(BOLO_WITH_LIBUSB)
    pkg_check_modules(LIBUSB IMPORTED_TARGET libusb-1.0)
    set(BOLO_HAVE_LIBUSB ${LIBUSB_FOUND})
  endif()
  if(BOLO_WITH_LIBGPIOD)
    pkg_check_modules(LIBGPIOD IMPORTED_TARGET libgpiod<2)
    set(BOLO_HAVE_LIBGPIOD ${LIBGPIOD_FOUND})
  endif()
endif()
if(BOLO_HAVE_LIBUSB)
  target_sources(bolo_hal_devices PRIVATE src/usb_libusb.cpp)
  target_link_libraries(bolo_hal_devices PUBLIC PkgConfig::LIBUSB)
  target_compile_definitions(bolo_hal_devices PUBLIC BOLO_HAVE_LIBUSB=1)
endif()
if(BOLO_HAVE_LIBGPIOD)
  target_link_libraries(bolo_hal_devices PUBLIC PkgConfig::LIBGPIOD)
  target_compile_definitions(bolo_hal_devices PUBLIC BOLO_HAVE_LIBGPIOD=1)
endif()
foreach(flag BOLO_HAVE_LIBUSB BOLO_HAVE_LIBGPIOD)
  if(NOT ${flag})
    set(${flag} OFF)
  endif()
endforeach()
message(STATUS "bolo HAL devices: libusb ${BOLO_HAVE_LIBUSB}, libgpiod ${BOLO_HAVE_LIBGPIOD}")
