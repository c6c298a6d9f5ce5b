#pragma once
// Linking tests/support/counting_allocator.cpp into a test binary replaces malloc, calloc,
// realloc and operator new there with versions that count calls while g_counting is set: how the
// allocation tests prove that code allocates nothing after initialisation. A sanitizer's runtime
// owns malloc and cannot share the process with a second replacement, so where one is compiled in
// (whatever flags brought it) nothing is replaced, BOLO_COUNTING_ALLOCATOR_ACTIVE is 0, and the
// allocation tests exit with kSkipExitCode (ctest: skipped).

#include <atomic>

#include "skip_exit_code.hpp"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define BOLO_COUNTING_ALLOCATOR_ACTIVE 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer) || __has_feature(leak_sanitizer)
#define BOLO_COUNTING_ALLOCATOR_ACTIVE 0
#endif
#endif
#ifndef BOLO_COUNTING_ALLOCATOR_ACTIVE
#define BOLO_COUNTING_ALLOCATOR_ACTIVE 1
#endif

namespace bolo::test {

extern std::atomic<long> g_allocations;
extern std::atomic<bool> g_counting;
// A probe allocation stored here escapes, so the compiler cannot elide the new/delete or
// malloc/free pair a test uses to prove that the counter sees allocations.
extern void* volatile g_escape;

}  // namespace bolo::test
