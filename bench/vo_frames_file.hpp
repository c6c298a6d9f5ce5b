#pragma once
// Rendered VO frames in a file, so a board build (without the host's renderer) runs the VO on the
// frames bolo-vo-bench renders: bolo-vo-bench --write-frames writes it, bolo-board-count vo reads
// it. Layout (native byte order): "BOLOVOF1", width, height, count (u32), fx, fy, cx, cy (f32),
// then count frames of width * height uint16.

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "bolo/vo/odometry.hpp"

namespace bolo::bench {

struct VoFrames {
  std::uint32_t width = 0, height = 0;
  vo::Camera camera;
  std::vector<std::vector<std::uint16_t>> frames;
};

inline constexpr char kVoFramesMagic[8] = {'B', 'O', 'L', 'O', 'V', 'O', 'F', '1'};
inline constexpr double kVoBenchFps = 60;

inline bool write_vo_frames(const char* path, const VoFrames& f) {
  std::FILE* out = std::fopen(path, "wb");
  if (out == nullptr) return false;
  const std::uint32_t head[3] = {f.width, f.height, static_cast<std::uint32_t>(f.frames.size())};
  const float camera[4] = {f.camera.fx, f.camera.fy, f.camera.cx, f.camera.cy};
  bool ok = std::fwrite(kVoFramesMagic, 1, 8, out) == 8 && std::fwrite(head, 4, 3, out) == 3 &&
            std::fwrite(camera, 4, 4, out) == 4;
  for (const auto& frame : f.frames)
    ok = ok && std::fwrite(frame.data(), 2, frame.size(), out) == frame.size();
  return std::fclose(out) == 0 && ok;
}

inline bool read_vo_frames(const char* path, VoFrames& f) {
  std::FILE* in = std::fopen(path, "rb");
  if (in == nullptr) return false;
  char magic[8];
  std::uint32_t head[3];
  float camera[4];
  bool ok = std::fread(magic, 1, 8, in) == 8 && std::memcmp(magic, kVoFramesMagic, 8) == 0 &&
            std::fread(head, 4, 3, in) == 3 && std::fread(camera, 4, 4, in) == 4 &&
            head[0] > 0 && head[1] > 0 && head[0] <= 8192 && head[1] <= 8192 && head[2] <= 100000;
  if (ok) {
    f.width = head[0], f.height = head[1];
    f.camera = {camera[0], camera[1], camera[2], camera[3]};
    f.frames.assign(head[2], std::vector<std::uint16_t>(std::size_t{head[0]} * head[1]));
    for (auto& frame : f.frames) ok = ok && std::fread(frame.data(), 2, frame.size(), in) == frame.size();
  }
  std::fclose(in);
  return ok;
}

// bolo-vo-bench's defaults: the ir model, tau 12 ms to start, the VO's defaults otherwise.
inline vo::VoConfig vo_bench_config(const VoFrames& f) {
  vo::VoConfig cfg;
  cfg.width = f.width, cfg.height = f.height, cfg.camera = f.camera;
  cfg.photometric = vo::Photometric::ir, cfg.tau_init_s = 0.012f;
  return cfg;
}

// Frame i at 60 Hz, exposure and readout half a period each (as bolo-vo-bench renders them).
inline vo::FrameInput vo_frame_input(const VoFrames& f, int i) {
  vo::FrameInput in;
  in.raw = f.frames[static_cast<std::size_t>(i)];
  in.t_s = i / kVoBenchFps, in.exposure_s = 0.5 / kVoBenchFps, in.readout_prev_s = 0.5 / kVoBenchFps;
  in.chain_broken = i == 0;
  return in;
}

}  // namespace bolo::bench
