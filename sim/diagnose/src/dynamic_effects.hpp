#pragma once
// Factories of the catalogue's candidates, by family (make_catalogue() lists them all).

#include <memory>
#include <vector>

#include "bolo/diagnose/candidate.hpp"

namespace bolo::diag {

std::unique_ptr<Candidate> make_thermal_memory();
std::unique_ptr<Candidate> make_tau_temperature();
std::unique_ptr<Candidate> make_rolling_readout();
std::unique_ptr<Candidate> make_crosstalk();
std::unique_ptr<Candidate> make_nonlinearity();
std::unique_ptr<Candidate> make_temporal_filter();

std::unique_ptr<Candidate> make_ffc_step();
std::unique_ptr<Candidate> make_fpa_drift();
std::unique_ptr<Candidate> make_frame_duplication();
std::unique_ptr<Candidate> make_agc();

std::unique_ptr<Candidate> make_offset_fpn();
std::unique_ptr<Candidate> make_column_fpn();
std::unique_ptr<Candidate> make_row_fpn();
std::unique_ptr<Candidate> make_shading();
std::unique_ptr<Candidate> make_gain_fpn();
std::unique_ptr<Candidate> make_tau_spread();
std::unique_ptr<Candidate> make_dead_pixels();

// d(baseline)/d(ln tau) through the two-frame recursion (for tau_spread).
void tau_derivative(const DiagnoseData& d, double tau_c, std::vector<float>& out);

}  // namespace bolo::diag
