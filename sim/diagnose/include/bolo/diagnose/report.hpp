#pragma once
// report.html: one self-contained page (inline SVG curves, base64 PNG maps) readable offline.

#include <filesystem>
#include <string>

#include "bolo/diagnose/diagnose.hpp"

namespace bolo::diag {

// `scratch` is a folder where temporary PNG files may be written (they are removed).
std::string render_report(const Diagnosis& d, const DiagnoseData& data, const ResidualViews& views,
                          const std::filesystem::path& scratch);

}  // namespace bolo::diag
