// The command's outputs: diagnosis.json in the contract's shape, a self-contained report, a
// simulator configuration that `bolo simulate --config` takes; refusals leave nothing behind.

#include <catch2/catch.hpp>

#include "diagnose_test_support.hpp"

using namespace bolo;
using namespace bolo::test;

TEST_CASE("diagnose writes diagnosis.json, report.html and simulate.cfg", "[diagnose][cli]") {
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
  refused({"diagnose", rec.string(), "--out", (tmp / "no" / "such" / "d").string()}, "no such folder");
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
