# Cross-compiling for 64-bit ARM camera boards (Cortex-A53/A72 class) with Debian's
# g++-aarch64-linux-gnu; tests run under qemu-aarch64.
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(BOLO_TRIPLET aarch64-linux-gnu)
set(BOLO_QEMU qemu-aarch64)
# ARMv8-A baseline (runs on every A53/A72 board), scheduled for the in-order A53 that most
# camera boards carry.
set(BOLO_CPU_FLAGS "-march=armv8-a -mtune=cortex-a53")
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
