#pragma once
// The depth search (depth_search.cpp): immature points' depths along their epipolar lines, and
// their activation. It keeps no state of its own.

#include <cstdint>

namespace bolo::vo {

struct MapCore;
struct State;

// Median inverse depth of the window's active points (0 when there are none; s.scratch is its scratch).
float typical_idepth(MapCore& s);
// extra_margin_px widens every match's interval (scale_bridge.cpp: a held turn's frames).
void search_immature_points(State& s, float extra_margin_px = 0.0f);
void activate_mature_points(State& s, std::uint32_t tracked_points);

}  // namespace bolo::vo
