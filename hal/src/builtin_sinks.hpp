#pragma once
// The built-in sinks, one file each; the registry (sink_registry.cpp) lists them in this order.

#include "bolo/hal/frame_sink.hpp"

namespace bolo::hal::detail {

SinkBackend recording_sink();  // sink_recording.cpp
SinkBackend raw_sink();        // sink_raw.cpp
SinkBackend v4l2_sink();       // sink_v4l2.cpp

}  // namespace bolo::hal::detail
