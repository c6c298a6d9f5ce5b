# Cross-compiling for 32-bit ARM camera boards (Cortex-A7/A9 class) with Debian's
# g++-arm-linux-gnueabihf; tests run under qemu-arm.
set(CMAKE_SYSTEM_PROCESSOR arm)
set(BOLO_TRIPLET arm-linux-gnueabihf)
set(BOLO_QEMU qemu-arm)
# ARMv7-A with NEON, hard-float ABI, Thumb-2: common to Cortex-A7 and Cortex-A9 SoCs used in
# camera boards (A9 parts without NEON need -mfpu=vfpv3-d16 instead).
set(BOLO_CPU_FLAGS "-march=armv7-a -mfpu=neon -mfloat-abi=hard -mthumb")
# GCC notes a 2017 ABI change for passing small structs; nothing here crosses that ABI.
set(BOLO_CXX_EXTRA_FLAGS "-Wno-psabi")
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
