#pragma once
// Per-CPU code selection on x86-64 with GCC (ifunc, glibc):
// * BOLO_KERNEL_CLONES: the same C++ loop compiled for x86-64-v4, AVX2 and the baseline; the
//   loader picks one. Integer code has one answer whatever the vector width.
// * BOLO_X86_KERNELS: 1 where the hand-written intrinsic kernels are built (picked at run time
//   with __builtin_cpu_supports, each tested against the portable loop).
// * BOLO_NEON_KERNELS: 1 on little-endian ARM compiled with NEON (aarch64; armhf with
//   -mfpu=neon) unless BOLO_NO_NEON: the NEON intrinsic kernels, chosen at build time, each
//   tested against the portable loop.
// Elsewhere (clang on x86, BOLO_NO_MULTIVERSION) only the portable loops are built.

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(BOLO_NO_MULTIVERSION)
#define BOLO_KERNEL_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#define BOLO_X86_KERNELS 1
#else
#define BOLO_KERNEL_CLONES
#define BOLO_X86_KERNELS 0
#endif

#if defined(__ARM_NEON) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__ && \
    !defined(BOLO_NO_NEON)
#define BOLO_NEON_KERNELS 1
#else
#define BOLO_NEON_KERNELS 0
#endif
