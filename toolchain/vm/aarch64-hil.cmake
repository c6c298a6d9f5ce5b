# The aarch64 cross toolchain plus the arm64 sysroot of toolchain/vm/arm64-sysroot.sh, so that
# libusb (and libgpiod) are found for the target: the HIL programs and the HAL's USB backends
# are then built for the arm64 HIL VM. Pass -DBOLO_HIL_SYSROOT=<printed path>.
include(${CMAKE_CURRENT_LIST_DIR}/../aarch64-linux-gnu.cmake)
# try_compile projects re-read this file without the cache: hand the variable on.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES BOLO_HIL_SYSROOT)
if(NOT BOLO_HIL_SYSROOT)
  message(FATAL_ERROR "aarch64-hil.cmake: set BOLO_HIL_SYSROOT (toolchain/vm/arm64-sysroot.sh prints it)")
endif()
set(ENV{PKG_CONFIG_LIBDIR} ${BOLO_HIL_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig)
set(ENV{PKG_CONFIG_SYSROOT_DIR} ${BOLO_HIL_SYSROOT})
set(CMAKE_EXE_LINKER_FLAGS_INIT
    "-Wl,-rpath-link,${BOLO_HIL_SYSROOT}/lib/aarch64-linux-gnu:${BOLO_HIL_SYSROOT}/usr/lib/aarch64-linux-gnu")
