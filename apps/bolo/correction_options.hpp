#pragma once
// The correction's options, which `bolo correct` and `bolo run` share: --tau-h, --tau-c,
// --exposure, --readout, --nuc, --bad-pixels, --nominal-fps, --max-faults.

#include <functional>

#include <CLI/CLI.hpp>

#include "bolo/correct/correct_recording.hpp"

namespace bolo::cli {

// Binds the options to `request` (which must outlive the command line); the returned function
// moves the optional ones that were given into it, once the command line is parsed.
std::function<void()> add_correction_options(CLI::App& app, correct::CorrectRequest& request);

}  // namespace bolo::cli
