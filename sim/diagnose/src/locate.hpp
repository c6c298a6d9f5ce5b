#pragma once
// Where a residual lives: profiles, spectra, event-locked averages and correlations with
// physical regressors (locate), and what remains structured after the findings (unexplained).

#include <vector>

#include <nlohmann/json.hpp>

#include "bolo/diagnose/diagnose.hpp"

namespace bolo::diag {

nlohmann::json locate(const DiagnoseData& d, const std::vector<float>& r, const Blocks& blocks);
std::vector<Unexplained> find_unexplained(const DiagnoseData& d, const std::vector<float>& r, const Blocks& blocks,
                                          double noise_floor);

}  // namespace bolo::diag
