#pragma once
// Linking tests/support/counting_allocator.cpp into a test binary replaces malloc, calloc,
// realloc and operator new there with versions that count calls while g_counting is set: how the
// allocation tests prove that code allocates nothing after initialisation. Not for sanitizer
// builds (their allocator cannot be replaced alongside).

#include <atomic>

namespace bolo::test {

extern std::atomic<long> g_allocations;
extern std::atomic<bool> g_counting;
// A probe allocation stored here escapes, so the compiler cannot elide the new/delete or
// malloc/free pair a test uses to prove that the counter sees allocations.
extern void* volatile g_escape;

}  // namespace bolo::test
