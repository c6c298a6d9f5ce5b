#pragma once
// The depth search (depth_search.cpp): immature points' depths along their epipolar lines, and
// their activation. It keeps no state of its own.

#include <cstdint>

namespace bolo::vo {

struct BrightnessTrack;
struct CurrentFrame;
struct InitialiserState;
struct MapCore;
struct MotionModel;
struct ScaleBridge;
struct TrackingReference;

// Median inverse depth of the window's active points (0 when there are none; s.scratch is its scratch).
float typical_idepth(MapCore& s);
// Narrows the immature points' inverse-depth intervals by their matches in the current frame f,
// posed at motion.T_cw with the brightness `brightness`. extra_margin_px widens every match's
// interval (scale_bridge.cpp: a held turn's frames).
void search_immature_points(MapCore& s, const CurrentFrame& f, const MotionModel& motion,
                            const BrightnessTrack& brightness, float extra_margin_px = 0.0f);
// Activates the immature points whose depth is known well enough (with tracked_points running
// short, also those a rotation keeps in view) and marks the tracking reference stale; points
// placed without a baseline break the map's scale at t_s (the scale bridge notes it).
void activate_mature_points(MapCore& s, TrackingReference& ref, ScaleBridge& bridge, const InitialiserState& init,
                            double t_s, std::uint32_t tracked_points);

}  // namespace bolo::vo
