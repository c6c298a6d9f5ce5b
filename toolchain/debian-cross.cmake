# Shared part of the Debian cross toolchain files: the caller sets BOLO_TRIPLET, BOLO_CPU_FLAGS,
# BOLO_QEMU and CMAKE_SYSTEM_PROCESSOR, then includes this file.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_C_COMPILER ${BOLO_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${BOLO_TRIPLET}-g++)
set(CMAKE_C_FLAGS_INIT "${BOLO_CPU_FLAGS}")
set(CMAKE_CXX_FLAGS_INIT "${BOLO_CPU_FLAGS} ${BOLO_CXX_EXTRA_FLAGS}")

# Debian multiarch: target libraries in /usr/lib/<triplet>, the cross sysroot in /usr/<triplet>;
# architecture-independent packages (nlohmann-json, Catch2) are found on the host paths.
set(CMAKE_LIBRARY_ARCHITECTURE ${BOLO_TRIPLET})
set(CMAKE_FIND_ROOT_PATH /usr/${BOLO_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${BOLO_TRIPLET}/pkgconfig:/usr/share/pkgconfig)

# ctest runs the cross-built tests under Debian's qemu-user with the target's loader and libraries.
set(CMAKE_CROSSCOMPILING_EMULATOR ${BOLO_QEMU} -L /usr/${BOLO_TRIPLET})
