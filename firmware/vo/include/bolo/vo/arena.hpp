#pragma once
// Hands out aligned pieces of one caller-provided buffer. The VO takes all its storage from an
// arena at construction, so nothing is allocated while frames stream.

#include <cstddef>
#include <cstdint>
#include <span>

namespace bolo::vo {

class Arena {
 public:
  Arena() = default;
  explicit Arena(std::span<std::byte> memory) : memory_(memory) {}

  // `count` default-initialised T, or an empty span when the arena is exhausted (`failed()`).
  template <typename T>
  std::span<T> take(std::size_t count) {
    const std::size_t align = alignof(T) < 16 ? 16 : alignof(T);
    // Align the address, not the offset: the caller's buffer may only be 8-byte aligned (new[]
    // on 32-bit ARM), and Eigen's NEON/SSE types fault or misbehave when misaligned.
    const auto base = reinterpret_cast<std::uintptr_t>(memory_.data());
    const std::size_t start = static_cast<std::size_t>((base + used_ + align - 1) / align * align - base);
    const std::size_t bytes = count * sizeof(T);
    if (start + bytes > memory_.size()) {
      failed_ = true;
      return {};
    }
    used_ = start + bytes;
    T* first = reinterpret_cast<T*>(memory_.data() + start);
    for (std::size_t i = 0; i < count; ++i) new (first + i) T();
    return {first, count};
  }
  std::size_t used() const { return used_; }
  bool failed() const { return failed_; }

 private:
  std::span<std::byte> memory_;
  std::size_t used_ = 0;
  bool failed_ = false;
};

}  // namespace bolo::vo
