#pragma once
// The backends the registry adds on first use (one file per family).

#include <vector>

#include "bolo/hal/source_registry.hpp"

namespace bolo::hal::detail {

void add_device_sources(std::vector<SourceBackend>& backends);     // sources_devices.cpp: cameras
void add_recording_sources(std::vector<SourceBackend>& backends);  // sources_recording.cpp
void add_replay_sources(std::vector<SourceBackend>& backends);     // sources_devices.cpp: logs

}  // namespace bolo::hal::detail
