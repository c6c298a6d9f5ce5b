// recording.json reading, writing and validation.

#include <cmath>

#include "rec_test_helpers.hpp"

using namespace bolo;
using bolo::test::contains;
using bolo::test::error_of;
using nlohmann::json;

namespace {

json valid_json() {
  return json::parse(R"({"format": "bolo-recording", "version": 1, "sensor": "FLIR Lepton 3.5",
      "width": 160, "height": 120, "bits": 14, "fps": 8.7, "units": "counts",
      "source": "test", "notes": "free text"})");
}

std::string json_error(const test::TempDir& tmp, const std::string& text) {
  const auto file = tmp / "recording.json";
  test::write_bytes(file, text);
  return error_of([&] { rec::read_recording_json(file); });
}

std::string json_error_of(const test::TempDir& tmp, const json& j) { return json_error(tmp, j.dump(2)); }

}  // namespace

TEST_CASE("recording.json: every field is read, unknown keys are kept and written back", "[json]") {
  test::TempDir tmp;
  const auto file = tmp / "recording.json";
  json j = valid_json();
  j["units"] = "centikelvin";
  j["lab"] = {{"blackbody", {20, 40}}, {"operator", "x"}};
  j["zzz"] = nullptr;
  test::write_bytes(file, j.dump());
  rec::RecordingInfo info = rec::read_recording_json(file);
  CHECK(info.sensor == "FLIR Lepton 3.5");
  CHECK(info.width == 160);
  CHECK(info.height == 120);
  CHECK(info.bits == 14);
  CHECK(info.fps == 8.7);
  CHECK(info.units == rec::Units::centikelvin);
  CHECK(info.source == "test");
  CHECK(info.notes == "free text");
  CHECK(info.extra == json{{"lab", j["lab"]}, {"zzz", nullptr}});

  rec::write_recording_json(file, info);
  const std::string text = test::read_bytes(file);
  CHECK(text.find("\"format\"") < text.find("\"width\""));  // spec order, extras after
  CHECK(text.find("\"notes\"") < text.find("\"lab\""));
  const rec::RecordingInfo back = rec::read_recording_json(file);
  CHECK(back.extra == info.extra);
  CHECK(back.fps == info.fps);
  CHECK(back.units == info.units);
  CHECK(json::parse(text)["format"] == "bolo-recording");
  CHECK(json::parse(text)["version"] == 1);
}

TEST_CASE("recording.json: optional keys may be absent or null", "[json]") {
  test::TempDir tmp;
  const auto file = tmp / "recording.json";
  test::write_bytes(file, R"({"format": "bolo-recording", "version": 1, "width": 80, "height": 60.0,
                              "fps": null})");
  const rec::RecordingInfo info = rec::read_recording_json(file);
  CHECK(info.width == 80);
  CHECK(info.height == 60);
  CHECK(info.units == rec::Units::counts);
  CHECK(info.bits == 16);
  CHECK(!info.fps);
  CHECK(info.sensor.empty());
  CHECK(info.extra.empty());
  CHECK(rec::to_string(rec::Units::counts8) == "counts8");
  CHECK(rec::to_string(rec::Units::centikelvin) == "centikelvin");
}

TEST_CASE("recording.json: a missing required field is named", "[json][bad-input]") {
  test::TempDir tmp;
  const std::string file = (tmp / "recording.json").string();
  for (const char* key : {"format", "version", "width", "height"}) {
    json j = valid_json();
    j.erase(key);
    CHECK(json_error_of(tmp, j) == file + ": field " + key + ": missing");
  }
}

TEST_CASE("recording.json: bad values are named with the field", "[json][bad-input]") {
  test::TempDir tmp;
  const std::string file = (tmp / "recording.json").string();
  struct Case {
    const char* key;
    json value;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"format", "bolo", ": field format: \"bolo\", expected \"bolo-recording\""},
      {"version", 2, ": field version: 2 is not supported (expected 1)"},
      {"width", -160, ": field width: -160, expected an integer from 1 to"},
      {"width", "160", ": field width: \"160\", expected an integer"},
      {"height", 0, ": field height: 0, expected an integer from 1 to"},
      {"height", 120.5, ": field height: 120.5, expected an integer"},
      {"bits", 64, ": field bits: 64, expected an integer from 1 to 32"},
      {"fps", 0, ": field fps: 0, expected > 0"},
      {"fps", -8.7, ": field fps: -8.7, expected > 0"},
      {"fps", "fast", ": field fps: \"fast\", expected a number"},
      {"units", "kelvin", ": field units: 'kelvin', expected counts, centikelvin or counts8"},
      {"sensor", 3, ": field sensor: 3, expected a string"},
  };
  for (const Case& c : cases) {
    json j = valid_json();
    j[c.key] = c.value;
    const std::string msg = json_error_of(tmp, j);
    INFO(msg);
    CHECK(msg.starts_with(file + c.expected));
  }
  CHECK(json_error(tmp, "[1, 2]") == file + ": expected a JSON object, got [1,2]");
}

TEST_CASE("recording.json: NaN, Infinity and overflowing numbers name the field", "[json][bad-input]") {
  test::TempDir tmp;
  const std::string file = (tmp / "recording.json").string();
  const std::string head = R"({"format": "bolo-recording", "version": 1, "width": 160, "height": 120, )";
  CHECK(contains(json_error(tmp, head + "\"fps\": NaN}"), file + ": field fps: NaN is not a finite number"));
  CHECK(contains(json_error(tmp, head + "\"fps\":\n  Infinity}"), file + ": field fps: Infinity"));
  CHECK(contains(json_error(tmp, head + "\"fps\": -Infinity}"), file + ": field fps: -Infinity"));
  CHECK(json_error(tmp, head + "\"fps\": 1e999}") == file + ": field fps: number out of range (1e999)");
}

TEST_CASE("recording.json: bad JSON syntax names the file and the position", "[json][bad-input]") {
  test::TempDir tmp;
  const std::string file = (tmp / "recording.json").string();
  std::string msg = json_error(tmp, "{\"format\": \"bolo-recording\",\n \"version\": 1,,}");
  CHECK(msg.starts_with(file + ": invalid JSON: parse error at line 2"));
  msg = json_error(tmp, "");
  CHECK(msg.starts_with(file + ": invalid JSON"));
  msg = json_error(tmp, "{\"format\": \"bolo-recording\"");
  CHECK(msg.starts_with(file + ": invalid JSON"));
  CHECK(contains(error_of([&] { rec::read_recording_json(tmp / "nope.json"); }), "nope.json: cannot open"));
}

TEST_CASE("recording.json: writing invalid info is refused", "[json][bad-input]") {
  test::TempDir tmp;
  const auto file = tmp / "recording.json";
  rec::RecordingInfo info = test::fixture_info();
  info.fps = std::nan("");
  CHECK(error_of([&] { rec::write_recording_json(file, info); }) == file.string() + ": field fps: not finite");
  info.fps = 0.0;
  CHECK(contains(error_of([&] { rec::write_recording_json(file, info); }), "field fps: 0, expected > 0"));
  info.fps.reset();
  info.width = 0;
  CHECK(contains(error_of([&] { rec::write_recording_json(file, info); }), "field width"));
  CHECK(!std::filesystem::exists(file));
}
