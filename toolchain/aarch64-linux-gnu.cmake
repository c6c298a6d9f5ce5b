# Cross-compiling for 64-bit ARM camera boards (Cortex-A53/A72 class) with Debian's
# g++-aarch64-linux-gnu; tests run under qemu-aarch64 (Debian's qemu-user).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(BOLO_TRIPLET aarch64-linux-gnu)

set(CMAKE_C_COMPILER ${BOLO_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${BOLO_TRIPLET}-g++)
# ARMv8-A baseline (runs on every A53/A72 board), scheduled for the in-order A53 that most
# camera boards carry.
set(CMAKE_C_FLAGS_INIT "-march=armv8-a -mtune=cortex-a53")
set(CMAKE_CXX_FLAGS_INIT "-march=armv8-a -mtune=cortex-a53")

# Debian multiarch: target libraries live in /usr/lib/aarch64-linux-gnu, headers in /usr/include.
set(CMAKE_LIBRARY_ARCHITECTURE ${BOLO_TRIPLET})
set(CMAKE_FIND_ROOT_PATH /usr/${BOLO_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${BOLO_TRIPLET}/pkgconfig:/usr/share/pkgconfig)

set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/${BOLO_TRIPLET})
