#pragma once
// The effect catalogue of ../shared/docs/diagnosis.md: one entry per effect id, holding its
// parameter schema, the simulator's half (a bolo::sim::Effect acting on the chain) and
// diagnose's half (a bolo::diag::Candidate that fits and predicts the effect's residual).
// Each family file in sim/effects/src defines its effects' entries with both halves.

#include <memory>
#include <string_view>
#include <vector>

#include "bolo/diagnose/candidate.hpp"
#include "bolo/effects/schema.hpp"
#include "bolo/sim/effect.hpp"

namespace bolo::effects {

using ApplyFactory = std::unique_ptr<sim::Effect> (*)(const sim::EffectSpec&, const sim::SimulationInfo&);
using FitFactory = std::unique_ptr<diag::Candidate> (*)();

struct EffectEntry {
  std::string_view id;
  std::vector<Param> params;
  ApplyFactory apply = nullptr;
  FitFactory fit = nullptr;
  // Where diagnose tries it in each selection round (0 first): events and global offsets before
  // static maps before transients, so an earlier, simpler effect wins a tie.
  int diagnosis_rank = 0;
};

// In the order the effects act along the simulation chain (catalogue.cpp says why).
const std::vector<EffectEntry>& catalogue();
// nullptr when no effect has that id.
const EffectEntry* find(std::string_view id);
// One diagnosis candidate per entry, in diagnosis_rank order.
std::vector<std::unique_ptr<diag::Candidate>> make_candidates();

}  // namespace bolo::effects
