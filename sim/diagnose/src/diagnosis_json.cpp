// diagnosis.json in the shape of ../shared/docs/diagnosis.md, and the simulator configuration of
// the fitted model.

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bolo/diagnose/diagnose.hpp"

namespace bolo::diag {
namespace {

// JSON has no NaN or infinity: unknown numbers are written as null.
nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json where_json(const Where& w) {
  nlohmann::json frames = nlohmann::json::array();
  for (auto [a, b] : w.frames) frames.push_back({a, b});
  return {{"frames", frames}, {"rows", {w.row0, w.row1}}, {"cols", {w.col0, w.col1}}, {"summary", w.summary}};
}

nlohmann::json evidence_json(const Evidence& e) {
  return {{"delta_bic", num(e.delta_bic)}, {"p_value", num(e.p_value)}, {"log_likelihood_ratio", num(e.log_likelihood_ratio)},
          {"block_z", num(e.block_z)}, {"n_eff", num(e.n_eff)}};
}

[[noreturn]] void bad(const std::string& field, const std::string& what) {
  throw std::runtime_error("diagnosis.json: field " + field + ": " + what);
}

const nlohmann::json& need(const nlohmann::json& j, const std::string& key, const std::string& path) {
  if (!j.is_object() || !j.contains(key)) bad(path + key, "missing");
  return j.at(key);
}

double need_number(const nlohmann::json& j, const std::string& key, const std::string& path, bool allow_null = false) {
  const nlohmann::json& v = need(j, key, path);
  if (allow_null && v.is_null()) return std::nan("");
  if (!v.is_number()) bad(path + key, "not a number");
  return v.get<double>();
}

Where read_where(const nlohmann::json& j, const std::string& path) {
  Where w;
  if (!j.is_object()) bad(path, "not an object");
  if (j.contains("frames")) {
    const auto& f = j.at("frames");
    if (!f.is_array()) bad(path + "frames", "not an array");
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto& r = f[i];
      if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
        bad(path + "frames[" + std::to_string(i) + "]", "not a [first, last] pair of integers");
      const auto a = r[0].get<long long>(), b = r[1].get<long long>();
      if (a < 0 || b < a || b > 1'000'000'000) bad(path + "frames[" + std::to_string(i) + "]", "not 0 <= first <= last");
      w.frames.push_back({int(a), int(b)});
    }
  }
  auto pair = [&](const char* key, int& lo, int& hi) {
    if (!j.contains(key)) return;
    const auto& r = j.at(key);
    if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
      bad(path + key, "not a [first, last] pair of integers");
    const auto a = r[0].get<long long>(), b = r[1].get<long long>();
    if (a < 0 || b < a || b > 1'000'000) bad(path + key, "not 0 <= first <= last");
    lo = int(a);
    hi = int(b);
  };
  pair("rows", w.row0, w.row1);
  pair("cols", w.col0, w.col1);
  if (j.contains("summary")) {
    if (!j.at("summary").is_string()) bad(path + "summary", "not a string");
    w.summary = j.at("summary").get<std::string>();
  }
  return w;
}

}  // namespace

nlohmann::json to_json(const Diagnosis& d) {
  nlohmann::json j;
  j["recording"] = d.recording;
  nlohmann::json baseline = d.baseline.to_json();
  for (auto& [k, v] : baseline["params"].items())
    if (v.is_number_float() && !std::isfinite(v.get<double>())) v = nullptr;
  baseline["fit_rms"] = num(d.fit_rms);
  baseline["heldout_rms"] = num(d.heldout_rms);
  j["baseline"] = baseline;
  j["noise_floor_rms"] = num(d.noise_floor_rms);
  j["findings"] = nlohmann::json::array();
  for (const Finding& f : d.findings) {
    j["findings"].push_back({{"effect", f.effect},
                             {"evidence", evidence_json(f.evidence)},
                             {"where", where_json(f.where)},
                             {"params", f.params},
                             {"simulator_effect", f.simulator_effect},
                             {"heldout_rms_before", num(f.heldout_rms_before)},
                             {"heldout_rms_after", num(f.heldout_rms_after)},
                             {"baseline_refit", f.baseline_refit}});
  }
  j["unexplained"] = nlohmann::json::array();
  for (const Unexplained& u : d.unexplained) j["unexplained"].push_back({{"where", where_json(u.where)}, {"rms", num(u.rms)}});
  j["heldout_rms_final"] = num(d.final_heldout_rms);
  nlohmann::json tried = nlohmann::json::array();
  for (const CandidateScore& s : d.scores)
    tried.push_back({{"round", s.round}, {"effect", s.effect}, {"accepted", s.accepted}, {"note", s.note},
                     {"evidence", evidence_json(s.evidence)}});
  j["candidates"] = tried;
  nlohmann::json locate = d.locate;
  locate.erase("frame_mean");
  locate.erase("frame_rms");
  locate.erase("spectrum");
  j["locate"] = locate;
  return j;
}

std::string simulator_config(const Diagnosis& d, const DiagnoseData& data) {
  // CLI11's config format: one `option = value` per line, repeatable options as arrays.
  std::ostringstream s;
  s.precision(8);
  s << "# bolo simulate --config FILE: the baseline and the effects bolo diagnose found in "
    << d.recording << "\n";
  s << "size = \"" << data.shape.width << "x" << data.shape.height << "\"\n";
  s << "fps = " << data.fps << "\n";
  s << "frames = " << data.shape.n << "\n";
  if (d.baseline.model == "two-frame") {
    // The time constants of the last refit: the model with every finding in it.
    double tau_h = d.baseline.tau_h_s, tau_c = d.baseline.tau_c_s;
    for (const Finding& f : d.findings)
      if (f.baseline_refit.is_object() && f.baseline_refit.contains("tau_c_s")) {
        tau_h = f.baseline_refit.value("tau_h_s", tau_h);
        tau_c = f.baseline_refit.value("tau_c_s", tau_c);
      }
    s << "tau-h = " << tau_h << "\n";
    s << "tau-c = " << tau_c << "\n";
  }
  s << "noise = " << d.noise_floor_rms << "\n";
  std::vector<std::string> effects;
  for (const Finding& f : d.findings)
    if (!f.simulator_effect.empty()) effects.push_back(f.simulator_effect);
  if (!effects.empty()) {
    s << "effect = [";
    for (std::size_t i = 0; i < effects.size(); ++i) s << (i ? ", " : "") << "\"" << effects[i] << "\"";
    s << "]\n";
  }
  return s.str();
}

Diagnosis read_diagnosis_json(const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("diagnosis.json: not JSON: ") + e.what());
  }
  if (!j.is_object()) bad("(top)", "not an object");
  Diagnosis d;
  const auto& rec = need(j, "recording", "");
  if (!rec.is_string()) bad("recording", "not a string");
  d.recording = rec.get<std::string>();
  const auto& base = need(j, "baseline", "");
  const auto& model = need(base, "model", "baseline.");
  if (!model.is_string()) bad("baseline.model", "not a string");
  d.baseline.model = model.get<std::string>();
  if (!need(base, "params", "baseline.").is_object()) bad("baseline.params", "not an object");
  d.fit_rms = need_number(base, "fit_rms", "baseline.", true);
  d.heldout_rms = need_number(base, "heldout_rms", "baseline.", true);
  d.noise_floor_rms = need_number(j, "noise_floor_rms", "", true);
  const auto& findings = need(j, "findings", "");
  if (!findings.is_array()) bad("findings", "not an array");
  for (std::size_t i = 0; i < findings.size(); ++i) {
    const std::string path = "findings[" + std::to_string(i) + "].";
    const auto& f = findings[i];
    Finding out;
    const auto& effect = need(f, "effect", path);
    if (!effect.is_string() || effect.get<std::string>().empty()) bad(path + "effect", "not a non-empty string");
    out.effect = effect.get<std::string>();
    const auto& ev = need(f, "evidence", path);
    out.evidence.delta_bic = need_number(ev, "delta_bic", path + "evidence.", true);
    out.evidence.p_value = need_number(ev, "p_value", path + "evidence.", true);
    out.where = read_where(need(f, "where", path), path + "where.");
    out.params = need(f, "params", path);
    if (!out.params.is_object()) bad(path + "params", "not an object");
    out.heldout_rms_before = need_number(f, "heldout_rms_before", path, true);
    out.heldout_rms_after = need_number(f, "heldout_rms_after", path, true);
    d.findings.push_back(std::move(out));
  }
  const auto& unexplained = need(j, "unexplained", "");
  if (!unexplained.is_array()) bad("unexplained", "not an array");
  for (std::size_t i = 0; i < unexplained.size(); ++i) {
    const std::string path = "unexplained[" + std::to_string(i) + "].";
    Unexplained u;
    u.where = read_where(need(unexplained[i], "where", path), path + "where.");
    u.rms = need_number(unexplained[i], "rms", path, true);
    d.unexplained.push_back(std::move(u));
  }
  return d;
}

}  // namespace bolo::diag
