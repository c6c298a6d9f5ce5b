#pragma once
// Which keyframe leaves a full window (keyframe_retirement.cpp).

#include <cstdint>

namespace bolo::vo {

struct MapCore;

// Which keyframe leaves a full window (its position in s.order, oldest first; s.scratch is
// scratch): the oldest, unless a keyframe between it and the two newest lies much nearer a
// neighbour along the path than the window's mean spacing (Retirement::spread). Such a keyframe
// was made for a turn, not for the distance travelled, and adds no baseline, while the oldest
// holds the window's longest one and, after a look-around, the view the camera comes back to. The
// most crowded such keyframe leaves.
std::uint32_t keyframe_to_retire(MapCore& s);

}  // namespace bolo::vo
