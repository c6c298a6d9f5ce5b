// The command's outputs: diagnosis.json in the contract's shape, a self-contained report, a
// simulator configuration that `bolo simulate --config` takes; refusals leave nothing behind.

#include <algorithm>
#include <fstream>

#include <catch2/catch.hpp>

#include "diagnose_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

TEST_CASE("diagnose writes diagnosis.json, report.html and simulate.cfg", "[diagnose][cli][long]") {
  TempDir tmp;
  const fs::path rec = simulate(tmp, "rec", {"column_fpn:sigma=3"}, 2);
  const nlohmann::json d = diagnose(rec, tmp / "out");
  CHECK(d["recording"] == "rec");
  CHECK(d["baseline"]["model"] == "two-frame");
  REQUIRE_FALSE(d["findings"].empty());
  CHECK(d["findings"][0]["effect"] == "column_fpn");
  const std::string html = read_text(tmp / "out" / "report.html");
  CHECK(html.find("<svg") != std::string::npos);
  CHECK(html.find("data:image/png;base64,") != std::string::npos);
  CHECK(html.find("column_fpn") != std::string::npos);
  CHECK(html.find("src='http") == std::string::npos);  // nothing fetched: readable offline
  CHECK(html.find("href=") == std::string::npos);

  // The fitted model simulates: same size and frame count, the column pattern back in truth/.
  const std::string cfg = read_text(tmp / "out" / "simulate.cfg");
  CHECK(cfg.find("column_fpn:sigma=") != std::string::npos);
  const CliResult s = run_bolo({"simulate", (tmp / "again").string(), "--config", (tmp / "out" / "simulate.cfg").string(),
                                "--substeps", "1"});
  INFO(s.err);
  REQUIRE(s.code == 0);
  const nlohmann::json truth = nlohmann::json::parse(read_text(tmp / "again" / "truth" / "effects.json"));
  CHECK(truth.dump().find("column_fpn") != std::string::npos);
  rec::Recording again(tmp / "again");
  CHECK(again.frame_count() == 120);
  CHECK(again.width() == 80);
}

TEST_CASE("diagnose refuses bad input with one line and leaves nothing", "[diagnose][cli]") {
  TempDir tmp;
  auto refused = [&](const std::vector<std::string>& args, const std::string& part) {
    const auto before = entries(tmp.path());
    const CliResult r = run_bolo(args);
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.rfind("bolo: error: ", 0) == 0);
    CHECK(r.err.find(part) != std::string::npos);
    CHECK(entries(tmp.path()) == before);
  };
  refused({"diagnose", (tmp / "missing").string(), "--out", (tmp / "d").string()}, "missing");
  const fs::path rec = simulate(tmp, "rec", {}, 1);
  refused({"diagnose", rec.string()}, "--out");
  refused({"diagnose", rec.string(), "--out", (tmp / "d").string(), "--folds", "1"}, "--folds");
  refused({"diagnose", rec.string(), "--out", rec.string()}, "already exists");
  refused({"diagnose", rec.string(), "--out", (tmp / "no" / "such" / "d").string()}, "does not exist");
}

TEST_CASE("read_diagnosis_json names the field that is wrong", "[diagnose][json]") {
  const std::string good =
      R"({"recording":"r","baseline":{"model":"two-frame","params":{},"fit_rms":1,"heldout_rms":1},)"
      R"("noise_floor_rms":1,"findings":[{"effect":"x","evidence":{"delta_bic":1,"p_value":0.1},)"
      R"("where":{"frames":[[1,2]]},"params":{},"heldout_rms_before":1,"heldout_rms_after":0.5}],"unexplained":[]})";
  CHECK(diag::read_diagnosis_json(good).findings.size() == 1);
  auto message = [](const std::string& text) {
    try {
      diag::read_diagnosis_json(text);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(message("[1]").find("not an object") != std::string::npos);
  CHECK(message("{").find("not JSON") != std::string::npos);
  std::string bad = good;
  bad.replace(bad.find("[[1,2]]"), 7, "[[2,1]]");
  CHECK(message(bad).find("findings[0].where.frames[0]") != std::string::npos);
  bad = good;
  bad.replace(bad.find("\"noise_floor_rms\":1"), 19, "\"noise_floor_rms\":\"a\"");
  CHECK(message(bad).find("noise_floor_rms") != std::string::npos);
}

TEST_CASE("diagnose: more refusals of docs/errors.md section 11", "[diagnose][cli]") {
  TempDir tmp;
  auto refused = [&](const std::vector<std::string>& args, const std::string& part) {
    const auto before = entries(tmp.path());
    const CliResult r = run_bolo(args);
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.rfind("bolo: error: ", 0) == 0);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find(part) != std::string::npos);
    CHECK(entries(tmp.path()) == before);
  };
  const fs::path one = simulate(tmp, "one", {}, 1, {"--frames", "1"});
  refused({"diagnose", one.string(), "--out", (tmp / "d").string()}, "diagnosis needs at least 2");
  refused({"diagnose", one.string(), "--out", (tmp / "d").string(), "--min-delta-bic", "-1"}, "--min-delta-bic");
  refused({"diagnose", "--out", (tmp / "d").string()}, "no recording given");
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(tmp / name) << text;
    return (tmp / name).string();
  };
  const std::string unknown = write("unknown.cfg", "bogus = 1\n");
  const std::string unterminated = write("unterminated.cfg", "size = \"80x60\n");
  const std::string not_number = write("nan.cfg", "fps = fast\n");
  const std::string no_equals = write("noeq.cfg", "fps 30\n");
  const std::string two = write("two.cfg", "fps = [1, 2]\n");
  refused({"simulate", (tmp / "s").string(), "--config", (tmp / "missing.cfg").string()}, "cannot read the --config file");
  refused({"simulate", (tmp / "s").string(), "--config", unknown}, "line 1: bogus: not an option of bolo simulate");
  refused({"simulate", (tmp / "s").string(), "--config", unterminated}, "line 1: unterminated string");
  refused({"simulate", (tmp / "s").string(), "--config", not_number}, "line 1: fps: not a number: 'fast'");
  refused({"simulate", (tmp / "s").string(), "--config", no_equals}, "line 1: expected `option = value`");
  refused({"simulate", (tmp / "s").string(), "--config", two}, "line 1: fps: expected one value, got 2");
  const std::string empty_list = write("empty.cfg", "fps = 30\neffect = [ ]\n");  // found by fuzzing
  refused({"simulate", (tmp / "s").string(), "--config", empty_list},
          "line 2: empty list: effect needs at least one value");
}

TEST_CASE("simulate --config: the command line wins over the file", "[diagnose][cli]") {
  TempDir tmp;
  std::ofstream(tmp / "c.cfg") << "size = \"40x30\"  # comment\nframes = 5\neffect = [\"column_fpn:sigma=2\"]\n";
  const CliResult r = run_bolo({"simulate", (tmp / "s").string(), "--config", (tmp / "c.cfg").string(), "--frames", "3"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  rec::Recording s(tmp / "s");
  CHECK(s.frame_count() == 3);
  CHECK(s.width() == 40);
  CHECK(read_text(tmp / "s" / "truth" / "effects.json").find("column_fpn") != std::string::npos);
}
