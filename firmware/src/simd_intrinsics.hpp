#pragma once
// The intrinsic headers of the kernels multiversion.hpp selects: <immintrin.h> where the x86
// kernels are built, <arm_neon.h> where the NEON ones are.

#include "multiversion.hpp"

#if BOLO_X86_KERNELS
// GCC 12's AVX-512 headers start some intrinsics from _mm512_undefined_epi32(), which its own
// -Wuninitialized then reports (GCC PR 105593, fixed in later releases). Silenced for these
// headers only: the diagnostics are attributed to lines inside them.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif
#if BOLO_NEON_KERNELS
#include <arm_neon.h>
#endif
