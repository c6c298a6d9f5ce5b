// Stuck pixels for the tau estimator (count_unchanged_frames in tau_estimator.cpp): a dead
// pixel among live ones is found within a few frames; a uniform region that never changes (a
// noise-free render) and live pixels of a low-noise camera are not taken for stuck.

#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "bolo/vo/arena.hpp"
#include "tau_truth_feed.hpp"
#include "state.hpp"

using namespace bolo;

TEST_CASE("stuck pixels are told from flat and from quiet live ones", "[vo][stuck]") {
  vo::VoConfig cfg;
  cfg.width = 48, cfg.height = 32;
  cfg.camera = {40.0f, 40.0f, 23.5f, 15.5f};
  cfg.photometric = vo::Photometric::ir;
  std::vector<std::byte> memory(vo::Odometry::arena_bytes(cfg));
  vo::Arena arena(memory);
  vo::State* s = vo::lay_out(cfg, arena);
  REQUIRE(s != nullptr);
  const std::uint32_t w = cfg.width;
  const auto at = [&](std::uint32_t x, std::uint32_t y) { return std::size_t{y} * w + x; };
  // Left half: a uniform surface, noise-free (never changes). Right half: a live scene at 8000
  // counts with quantised noise of 1 count (often the same value two frames running).
  // One dead pixel (0) and one at full scale in the live half.
  const std::size_t dead = at(36, 16), hot = at(26, 8), quiet = at(30, 20), flat = at(10, 10), edge = at(23, 12);
  test::ApproxNormal noise(5);
  const auto frame = [&](std::span<float> raw) {
    for (std::uint32_t y = 0; y < cfg.height; ++y)
      for (std::uint32_t x = 0; x < w; ++x)
        raw[at(x, y)] = x < w / 2 ? 6000.0f : static_cast<float>(std::lround(8000.0 + noise()));
    raw[dead] = 0.0f;
    raw[hot] = 65535.0f;
  };
  frame(s->current.raw);
  int quiet_worst = 0;
  for (int k = 1; k <= 40; ++k) {
    std::swap(s->current.raw, s->current.raw_prev);
    frame(s->current.raw);
    vo::count_unchanged_frames(s->tau_est, s->current, *s);
    quiet_worst = std::max<int>(quiet_worst, s->tau_est.unchanged_frames[quiet]);
    if (k == 8) {
      CHECK(s->tau_est.unchanged_frames[dead] >= 4);  // checked every other frame: stuck after 8 frames
      CHECK(s->tau_est.unchanged_frames[hot] >= 4);
    }
  }
  CHECK(s->tau_est.unchanged_frames[flat] == 0);
  CHECK(s->tau_est.unchanged_frames[edge] == 0);  // the uniform surface's edge, next to the live half
  // A live pixel may keep its value a frame or two, but it does not stand out from its
  // neighbours by 64 counts, so it is never counted.
  CHECK(quiet_worst == 0);
  std::size_t stuck = 0;
  for (const std::uint8_t c : s->tau_est.unchanged_frames) stuck += c >= 4;
  CHECK(stuck == 2);
}
