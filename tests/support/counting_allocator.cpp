// The counting allocator of counting_allocator.hpp: forwards to glibc's own entry points.

#include "counting_allocator.hpp"

#include <cstdlib>
#include <new>

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void __libc_free(void*);
}

namespace bolo::test {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
void* volatile g_escape = nullptr;
}  // namespace bolo::test

#if BOLO_COUNTING_ALLOCATOR_ACTIVE
namespace {
void note() {
  if (bolo::test::g_counting.load(std::memory_order_relaxed)) bolo::test::g_allocations.fetch_add(1);
}
}  // namespace

extern "C" {
void* malloc(std::size_t n) {
  note();
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t size) {
  note();
  return __libc_calloc(n, size);
}
void* realloc(void* p, std::size_t n) {
  note();
  return __libc_realloc(p, n);
}
void free(void* p) { __libc_free(p); }
}

void* operator new(std::size_t n) {
  note();
  if (void* p = __libc_malloc(n ? n : 1)) return p;
  std::abort();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }
#endif  // BOLO_COUNTING_ALLOCATOR_ACTIVE
