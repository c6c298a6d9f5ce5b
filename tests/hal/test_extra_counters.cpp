// ExtraCounters: the counters a source keeps beyond SourceStats, by name; a wrapping source
// (FaultInjector) passes its inner source's on.

#include <catch2/catch.hpp>

#include <string>

#include "bolo/hal/fault_injector.hpp"

using namespace bolo;

namespace {

// A source with two counters of its own and no frames.
class CountingSource final : public hal::FrameSource {
 public:
  hal::SourceFormat format() const override { return {4, 2, 16, hal::PixelUnits::counts, 0}; }
  hal::StreamStatus stream_frame(fw::LineSink&) override { return hal::StreamStatus::end_of_stream; }
  hal::SourceStats stats() const override { return {}; }
  hal::ExtraCounters extra_counters() const override {
    hal::ExtraCounters c;
    c.add("skipped_in_camera", 3);
    c.add("counter_jumps", 0);
    return c;
  }
};

}  // namespace

TEST_CASE("extra counters: kept in order with their names, zeros included, found by name", "[hal]") {
  const hal::ExtraCounters c = CountingSource().extra_counters();
  REQUIRE(c.items().size() == 2);
  CHECK(c.items()[0].name == "skipped_in_camera");
  CHECK(c.items()[0].value == 3);
  CHECK(c.items()[1].name == "counter_jumps");
  CHECK(c.items()[1].value == 0);
  REQUIRE(c.find("counter_jumps") != nullptr);
  CHECK(c.find("counter_jumps")->value == 0);
  CHECK(c.find("out_of_order") == nullptr);
}

TEST_CASE("extra counters: a source without any reports none, a full list keeps its first ones", "[hal]") {
  CHECK(hal::ExtraCounters{}.items().empty());
  static const std::string names[hal::ExtraCounters::kCapacity + 1] = {
      "c0", "c1", "c2", "c3", "c4", "c5", "c6", "c7", "c8", "c9", "c10", "c11", "c12", "c13", "c14", "c15", "c16"};
  hal::ExtraCounters c;
  for (std::size_t i = 0; i <= hal::ExtraCounters::kCapacity; ++i) c.add(names[i], i);
  CHECK(c.items().size() == hal::ExtraCounters::kCapacity);
  CHECK(c.items().back().name == "c15");
  CHECK(c.find("c16") == nullptr);
}

TEST_CASE("extra counters: the fault injector passes its inner source's on", "[hal][faults]") {
  CountingSource inner;
  hal::FaultInjector injector(inner, {});
  const hal::ExtraCounters c = injector.extra_counters();
  REQUIRE(c.find("skipped_in_camera") != nullptr);
  CHECK(c.find("skipped_in_camera")->value == 3);
  CHECK(c.items().size() == 2);
}
