# Cross-compiling for 32-bit ARM camera boards (Cortex-A7/A9 class) with Debian's
# g++-arm-linux-gnueabihf; tests run under qemu-arm (Debian's qemu-user).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(BOLO_TRIPLET arm-linux-gnueabihf)

set(CMAKE_C_COMPILER ${BOLO_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${BOLO_TRIPLET}-g++)
# ARMv7-A with NEON, hard-float ABI, Thumb-2: common to Cortex-A7 and Cortex-A9 SoCs used in
# camera boards (A9 parts without NEON need -mfpu=vfpv3-d16 instead).
set(CMAKE_C_FLAGS_INIT "-march=armv7-a -mfpu=neon -mfloat-abi=hard -mthumb")
# -Wno-psabi: GCC notes a 2017 ABI change for passing small structs; nothing here crosses that ABI.
set(CMAKE_CXX_FLAGS_INIT "-march=armv7-a -mfpu=neon -mfloat-abi=hard -mthumb -Wno-psabi")

set(CMAKE_LIBRARY_ARCHITECTURE ${BOLO_TRIPLET})
set(CMAKE_FIND_ROOT_PATH /usr/${BOLO_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${BOLO_TRIPLET}/pkgconfig:/usr/share/pkgconfig)

set(CMAKE_CROSSCOMPILING_EMULATOR qemu-arm -L /usr/${BOLO_TRIPLET})
