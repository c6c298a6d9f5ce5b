#pragma once
// The integer type that stores a fixed-point number of a given width.

#include <cstdint>
#include <type_traits>

namespace bolo::fx::detail {

// The smallest of int8/16/32/64 (or their unsigned forms) with at least `Bits` bits, sign
// included.
template <int Bits, bool Signed>
struct storage_for {
  static_assert(Bits >= 1 && Bits <= 64, "a fixed-point format needs 1 to 64 bits of storage");
  using unsigned_type =
      std::conditional_t<(Bits <= 8), std::uint8_t,
                         std::conditional_t<(Bits <= 16), std::uint16_t,
                                            std::conditional_t<(Bits <= 32), std::uint32_t,
                                                               std::uint64_t>>>;
  using type = std::conditional_t<Signed, std::make_signed_t<unsigned_type>, unsigned_type>;
};

template <int Bits, bool Signed>
using storage_t = typename storage_for<Bits, Signed>::type;

}  // namespace bolo::fx::detail
