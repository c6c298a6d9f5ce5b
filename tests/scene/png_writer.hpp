#pragma once
// Test-only: write a temperature image as an 8-bit false-colour PNG to look at.
#include <filesystem>
#include <span>

namespace bolo::test {

// Kelvin in [lo_k, hi_k] mapped to an "ironbow" palette (black-blue-purple-orange-yellow-white);
// values outside clip.
void write_temperature_png(const std::filesystem::path& file, std::uint32_t width, std::uint32_t height,
                           std::span<const float> kelvin, float lo_k, float hi_k);

}  // namespace bolo::test
