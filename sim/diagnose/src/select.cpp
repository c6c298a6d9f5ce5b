// Greedy forward selection over the catalogue with held-out blocks (diagnose.hpp).

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "bolo/diagnose/diagnose.hpp"
#include "bolo/effects/catalogue.hpp"
#include "locate.hpp"
#include "bolo/effects/scene_flow.hpp"
#include "bolo/effects/stats.hpp"

namespace bolo::diag {
namespace {

struct FrameSse {
  std::vector<double> sse, count;
};

FrameSse frame_sse(const DiagnoseData& d, const std::vector<float>& r) {
  FrameSse s;
  const std::size_t P = d.shape.pixels();
  s.sse.assign(d.shape.n, 0);
  s.count.assign(d.shape.n, 0);
  for (int n = 0; n < d.shape.n; ++n) {
    const float* f = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    double a = 0, c = 0;
    for (std::size_t p = 0; p < P; ++p)
      if (v[p]) { a += double(f[p]) * f[p]; c += 1; }
    s.sse[n] = a;
    s.count[n] = c;
  }
  return s;
}

// (r + B) ~ gain B + offset over the valid pixel-frames: the baseline B rescaled to the
// recording minus what the findings explain.
struct GainOffset {
  double gain = 1, offset = 0, sse_before = 0, sse_after = 0;
};
GainOffset refit_gain_offset(const DiagnoseData& d, const std::vector<float>& r) {
  double n = 0, sb = 0, sy = 0, sbb = 0, sby = 0, syy = 0, srr = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (!d.valid[i]) continue;
    const double b = d.baseline[i], y = double(r[i]) + b;
    n += 1; sb += b; sy += y; sbb += b * b; sby += b * y; syy += y * y; srr += double(r[i]) * r[i];
  }
  GainOffset g;
  g.sse_before = g.sse_after = srr;
  const double vb = sbb - sb * sb / n, cby = sby - sb * sy / n, vy = syy - sy * sy / n;
  if (!(n > 2) || !(vb > 1e-12 * std::max(1.0, sbb))) return g;
  g.gain = cby / vb;
  g.offset = (sy - g.gain * sb) / n;
  g.sse_after = std::max(0.0, vy - g.gain * cby);
  return g;
}

// How many independent samples the valid pixel-frames are worth: a residual shared by all
// pixels of a frame, or carried from frame to frame, counts less (design effect).
double effective_samples(const DiagnoseData& d, const std::vector<float>& r, const FrameSse& s) {
  const std::size_t P = d.shape.pixels();
  double total = 0, sse = 0, lag = 0, lag_norm = 0;
  std::vector<double> mean(d.shape.n, 0.0);
  for (int n = 0; n < d.shape.n; ++n) {
    total += s.count[n];
    sse += s.sse[n];
    const float* f = d.frame(r, n);
    const std::uint8_t* v = d.valid_frame(n);
    double m = 0;
    for (std::size_t p = 0; p < P; ++p)
      if (v[p]) m += f[p];
    mean[n] = s.count[n] > 0 ? m / s.count[n] : 0;
    if (n > 0) {
      const float* g = d.frame(r, n - 1);
      const std::uint8_t* w = d.valid_frame(n - 1);
      for (std::size_t p = 0; p < P; ++p)
        if (v[p] && w[p]) { lag += double(f[p]) * g[p]; lag_norm += double(f[p]) * f[p]; }
    }
  }
  if (total <= 0 || sse <= 0) return 1.0;
  const double var = sse / total;
  double vm = 0;
  for (int n = 0; n < d.shape.n; ++n) vm += mean[n] * mean[n];
  vm /= d.shape.n;
  const double per_frame = total / d.shape.n;
  const double rho_s = std::clamp((vm - var / per_frame) / var, 0.0, 1.0);
  const double rho_t = std::clamp(lag_norm > 0 ? lag / lag_norm : 0.0, 0.0, 0.95);
  const double inflation = (1 + (per_frame - 1) * rho_s) * (1 + rho_t) / (1 - rho_t);
  return std::max(1.0, total / inflation);
}

// The residual's variance about each pixel's own mean, over pixels where the baseline holds still
// in every frame (unbiased per pixel). The frame-difference noise floor understates the noise
// variance where the noise is correlated from frame to frame (an in-core filter keeps part of the
// previous frame's noise: the floor sees sigma^2 (1 - rho)); this is the other side of it. 0 when
// fewer than 100 pixels hold still throughout.
double still_pixel_variance(const DiagnoseData& d, const std::vector<float>& r) {
  const int N = d.shape.n;
  const std::size_t P = d.shape.pixels();
  std::vector<double> sum(P, 0.0), squares(P, 0.0), count(P, 0.0);
  std::vector<char> still(P, 1);
  for (int n = 0; n < N; ++n) {
    const float *b = d.frame(d.still_reference(), n), *f = d.frame(r, n);
    const float* b0 = n > 0 ? d.frame(d.still_reference(), n - 1) : b;
    const std::uint8_t* v = d.valid_frame(n);
    for (std::size_t p = 0; p < P; ++p) {
      if (!still[p]) continue;
      if (!holds_still(b[p], b0[p])) { still[p] = 0; continue; }
      if (!v[p]) continue;
      sum[p] += f[p], squares[p] += double(f[p]) * f[p], count[p] += 1;
    }
  }
  double ss = 0, dof = 0, pixels = 0;
  for (std::size_t p = 0; p < P; ++p) {
    if (!still[p] || count[p] < 8) continue;
    ss += squares[p] - sum[p] * sum[p] / count[p];
    dof += count[p] - 1;
    pixels += 1;
  }
  return pixels >= 100 && dof > 0 ? ss / dof : 0.0;
}

struct Scored {
  Evidence evidence;
  double sse_before_all = 0, sse_after_all = 0, count_all = 0;  // every held-out frame (for RMS)
  std::vector<double> frame_gain;  // held-out SSE reduction per frame
  bool fitted = false;
};

Scored score(const Candidate& c, const DiagnoseData& d, const std::vector<float>& r, const Blocks& blocks,
             const FrameSse& before, std::vector<float>& after_r) {
  Scored out;
  const int N = d.shape.n;
  const std::size_t P = d.shape.pixels();
  out.frame_gain.assign(N, 0.0);
  std::vector<float> pred(P);
  std::vector<double> after = before.sse;
  std::vector<char> acted(N, 0);
  after_r = r;
  for (int k = 0; k < blocks.folds; ++k) {
    std::vector<char> train(N);
    for (int n = 0; n < N; ++n) train[n] = blocks.fold_of_frame(n) != k;
    auto model = c.fit(train);
    if (!model) return out;
    for (int n = 0; n < N; ++n) {
      if (train[n] || !model->acts_on(n)) continue;
      acted[n] = 1;
      model->predict(n, pred);
      const float* f = d.frame(r, n);
      float* a = d.frame(after_r, n);
      const std::uint8_t* v = d.valid_frame(n);
      double s = 0;
      for (std::size_t p = 0; p < P; ++p) {
        a[p] = f[p] - pred[p];
        if (v[p]) s += double(a[p]) * a[p];
      }
      after[n] = s;
    }
  }
  out.fitted = true;
  std::vector<double> block_gain(blocks.count, 0.0);
  Evidence& e = out.evidence;
  for (int n = 0; n < N; ++n) {
    out.frame_gain[n] = before.sse[n] - after[n];
    block_gain[blocks.block_of_frame[n]] += out.frame_gain[n];
    out.sse_before_all += before.sse[n];
    out.sse_after_all += after[n];
    out.count_all += before.count[n];
    if (c.scored_where_it_acts() && !acted[n]) continue;
    e.sse_before += before.sse[n];
    e.sse_after += after[n];
    e.count += before.count[n];
  }
  double sum = 0, sum2 = 0;
  for (double g : block_gain) { sum += g; sum2 += g * g; }
  e.block_z = sum2 > 0 ? sum / std::sqrt(sum2) : 0.0;
  // The sample size of the test is judged on what the alternative leaves: the effect's own
  // structure must not count against it, shared or carried-over noise must.
  FrameSse left{after, before.count};
  e.n_eff = effective_samples(d, after_r, left);
  if (e.sse_after > 0 && e.sse_before > 0) {
    e.log_likelihood_ratio = e.n_eff * std::log(e.sse_before / e.sse_after);
    e.delta_bic = e.log_likelihood_ratio - c.parameter_count() * std::log(std::max(2.0, e.n_eff));
    e.p_value = chi2_sf(e.log_likelihood_ratio, c.parameter_count());
  } else if (e.sse_after <= 0 && e.sse_before > 0) {
    e.log_likelihood_ratio = e.delta_bic = kExactEvidence;  // explains held-out data exactly
    e.p_value = 0;
  }
  return out;
}

// Frame ranges where a finding's held-out gain concentrates.
std::vector<std::pair<int, int>> active_frames(const std::vector<double>& gain) {
  const int N = static_cast<int>(gain.size());
  const int w = std::max(1, N / 50);
  std::vector<double> smooth(N, 0.0);
  for (int n = 0; n < N; ++n) {
    double s = 0;
    for (int m = std::max(0, n - w); m <= std::min(N - 1, n + w); ++m) s += gain[m];
    smooth[n] = s;
  }
  const double peak = *std::max_element(smooth.begin(), smooth.end());
  std::vector<std::pair<int, int>> ranges;
  if (!(peak > 0)) return ranges;
  for (int n = 0; n < N; ++n) {
    if (smooth[n] < 0.2 * peak) continue;
    if (!ranges.empty() && n - ranges.back().second <= w + 1) ranges.back().second = n;
    else ranges.push_back({n, n});
  }
  if (ranges.size() > 12) ranges = {{ranges.front().first, ranges.back().second}};
  return ranges;
}

double rms_of(double sse, double count) { return count > 0 ? std::sqrt(sse / count) : 0.0; }

}  // namespace

void keep_freed_memory_for_reuse() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_MAX, 0);             // large blocks from the heap, not mapped one by one
  mallopt(M_TRIM_THRESHOLD, INT_MAX);  // and not handed back to the system when freed
#endif
}

Diagnosis diagnose(DiagnoseData& data, const Options& options, ResidualViews* views, const ProgressFn& progress) {
  auto report = [&](const std::string& stage, int done, int total) {
    if (progress) progress(stage, done, total);
  };
  Diagnosis result;
  result.recording = data.name;
  report("baseline", 0, 1);
  result.baseline = fit_baseline(data);
  nlohmann::json baseline_params = result.baseline.to_json()["params"];  // as refitted after findings
  data.tau_c_s = data.has_scene ? result.baseline.tau_c_s : 0.0;
  data.gain = result.baseline.gain;
  if (data.has_scene && data.input_flow_dy.empty()) fill_input_flow(data);  // for the candidates' rates of change along the scene's motion
  const int N = data.shape.n;
  const std::size_t P = data.shape.pixels();
  // A shutter frame reads the shutter, not the scene.
  auto invalidate_events = [&] {
    for (int n = 0; n < N; ++n)
      if (data.flagged_event[n]) std::fill_n(data.valid.begin() + std::size_t(n) * P, P, 0);
  };
  const std::vector<std::uint8_t> moving_mask = data.valid;
  invalidate_events();
  std::vector<float> r(data.shape.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = data.recorded[i] - data.baseline[i];
  result.noise_floor_rms = noise_floor(data);
  const Blocks blocks = make_blocks(N, options.folds);
  const Blocks far_blocks = halves(blocks);
  result.locate = locate(data, r, blocks);

  FrameSse before = frame_sse(data, r);
  {
    double s = 0, c = 0;
    for (int n = 0; n < N; ++n) { s += before.sse[n]; c += before.count[n]; }
    result.fit_rms = rms_of(s, c);
    // The baseline's own held-out error: its few global parameters were fitted on all frames,
    // so this is its in-sample RMS corrected by the parameters' share of the samples.
    const double k = data.has_scene ? 3.0 : double(P);
    result.heldout_rms = rms_of(s, std::max(1.0, c - k));
  }
  if (views) views->before = r;
  auto candidates = effects::make_candidates();
  std::vector<char> used(candidates.size(), 0);
  const int rounds = std::min<int>(options.max_findings, int(candidates.size()));
  std::vector<float> after_r;
  for (int round = 0; round < rounds; ++round) {
    // Stop at the noise floor: once the findings bring the residual down to the temporal noise,
    // what is left is noise (the first round is always tried: a concealed effect can sit under a
    // floor estimate that is a little high).
    if (round > 0) {
      double s = 0, c = 0;
      for (int n = 0; n < N; ++n) { s += before.sse[n]; c += before.count[n]; }
      if (rms_of(s, c) <= result.noise_floor_rms) break;
    }
    int best = -1;
    Scored best_score;
    // The share rule needs a simulation to be measured against: without a scene the background
    // is the recording's own median, every pixel counts as still, and the moving objects the mask
    // lets through are most of the "mismatch".
    const double noise_variance =
        data.has_scene ? std::max(result.noise_floor_rms * result.noise_floor_rms, still_pixel_variance(data, r)) : 0.0;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (used[i]) continue;
      report("round " + std::to_string(round + 1) + " " + candidates[i]->id(), int(i), int(candidates.size()));
      candidates[i]->prepare(data, r);
      Scored s = score(*candidates[i], data, r, candidates[i]->needs_distant_holdout() ? far_blocks : blocks, before,
                       after_r);
      CandidateScore cs{round + 1, candidates[i]->id(), s.evidence, false, s.fitted ? "" : "nothing to fit"};
      const double signature_z = candidates[i]->signature_z();
      candidates[i]->release();
      result.scores.push_back(cs);
      // Practical floor: what the effect explains must be a visible share of the noise, or a
      // tiny imperfection of the baseline pooled over millions of samples would count. A
      // candidate with a signature of its own, which no such imperfection makes, is judged by its z.
      const double samples = std::max(1.0, s.evidence.count);
      const double explained = (s.evidence.sse_before - s.evidence.sse_after) / samples;
      const double floor = options.min_explained_share * result.noise_floor_rms;
      // Material: a fifth of what is there to explain (Options::min_mismatch_share).
      const double mismatch = s.evidence.sse_before / samples - noise_variance;
      const bool by_signature = std::isfinite(signature_z);
      const bool visible = by_signature ? signature_z > options.min_signature_z : explained >= floor * floor;
      const bool material = by_signature || !data.has_scene || explained >= options.min_mismatch_share * mismatch;
      // The numbers the two rules compared (held-out mean squares per pixel-frame).
      auto against = [&](double limit) {
        char text[96];
        std::snprintf(text, sizeof text, " (explained %.3g of %.3g)", explained, limit);
        return std::string(text);
      };
      if (s.fitted && by_signature) {
        char text[112];
        std::snprintf(text, sizeof text, visible ? "judged by its signature (z %.2f above %.3g)"
                                                 : "its signature is not clear of sampling error (z %.2f of %.3g)",
                      signature_z, options.min_signature_z);
        result.scores.back().note = text;
      } else if (s.fitted && !visible) result.scores.back().note = "below the practical floor" + against(floor * floor);
      else if (s.fitted && !material) result.scores.back().note = "a small share of the mismatch" + against(mismatch);
      const bool passes = s.fitted && visible && material && s.evidence.delta_bic > options.min_delta_bic &&
                          s.evidence.block_z > options.min_block_z && s.evidence.sse_after < s.evidence.sse_before;
      if (passes && (best < 0 || s.evidence.delta_bic > best_score.evidence.delta_bic)) {
        best = int(i);
        best_score = std::move(s);
      }
    }
    if (best < 0) break;
    for (auto& cs : result.scores)
      if (cs.round == round + 1 && cs.effect == candidates[best]->id()) cs.accepted = true;
    Candidate& c = *candidates[best];
    c.prepare(data, r);
    std::vector<char> all(N, 1);
    auto model = c.fit(all);
    c.release();
    Finding f;
    f.effect = c.id();
    f.evidence = best_score.evidence;
    f.params = model->params();
    f.simulator_effect = model->simulator_effect();
    f.where = model->where();
    if (f.where.frames.size() == 1 && f.where.frames[0] == std::pair<int, int>{0, N - 1}) {
      auto active = active_frames(best_score.frame_gain);
      if (!active.empty()) f.where.frames = active;
    }
    f.heldout_rms_before = rms_of(best_score.sse_before_all, best_score.count_all);
    f.heldout_rms_after = rms_of(best_score.sse_after_all, best_score.count_all);
    // Backwards, so an effect reading the previous frame's residual sees it unchanged.
    std::vector<float> pred(P);
    for (int n = N - 1; n >= 0; --n) {
      if (!model->acts_on(n)) continue;
      model->predict(n, pred);
      float* rf = data.frame(r, n);
      for (std::size_t p = 0; p < P; ++p) rf[p] -= pred[p];
    }
    used[best] = 1;
    if (data.has_scene) {
      // The baseline's tau, gain and offset again, on the recording minus what the findings
      // explain: an effect the frozen baseline had absorbed (a filter into tau) lets go of it.
      std::vector<float> original = std::move(data.recorded);
      data.recorded.resize(r.size());
      for (std::size_t i = 0; i < r.size(); ++i) data.recorded[i] = r[i] + data.baseline[i];
      const std::vector<float> kept_baseline = data.baseline;
      const double kept_tau = data.tau_c_s, kept_gain = data.gain;
      const FrameSteps kept_steps = data.steps, kept_steps_per_ln_tau = data.steps_per_ln_tau;
      std::vector<float> kept_within_exposure = data.within_exposure;
      const BaselineFit refit = fit_baseline(data);
      data.tau_c_s = refit.tau_c_s;
      data.gain = refit.gain;
      std::vector<float> refit_r(r.size());
      for (std::size_t i = 0; i < r.size(); ++i) refit_r[i] = data.recorded[i] - data.baseline[i];
      data.recorded = std::move(original);
      data.valid = moving_mask;
      invalidate_events();
      // The refit is a least-squares fit of the same model with one more effect taken out: it
      // can only lower the residual. If it did not (a fit that ran off to a bound), keep the
      // baseline the effect was scored against.
      const FrameSse refit_sse = frame_sse(data, refit_r), kept_sse = frame_sse(data, r);
      double refit_total = 0, kept_total = 0;
      for (int n = 0; n < N; ++n) { refit_total += refit_sse.sse[n]; kept_total += kept_sse.sse[n]; }
      if (std::isfinite(refit_total) && refit_total <= kept_total) {
        r = std::move(refit_r);
        f.baseline_refit = refit.to_json()["params"];
        baseline_params = f.baseline_refit;
      } else {
        data.baseline = kept_baseline;
        data.tau_c_s = kept_tau;
        data.gain = kept_gain;
        data.steps = kept_steps;
        data.steps_per_ln_tau = kept_steps_per_ln_tau;
        data.within_exposure = std::move(kept_within_exposure);
        f.baseline_refit = nullptr;
        // Gain and offset alone, by least squares on the pixel-frames the residual is measured on,
        // can only lower it: a gain the finding's signature had pulled must not be left for the
        // next candidate's free gain (agc's) to collect.
        const GainOffset g = refit_gain_offset(data, r);
        if (g.sse_after < g.sse_before) {
          for (std::size_t i = 0; i < r.size(); ++i) {
            const float b = data.baseline[i];
            data.baseline[i] = static_cast<float>(g.gain * b + g.offset);
            r[i] += b - data.baseline[i];
          }
          data.gain *= g.gain;
          baseline_params["gain"] = data.gain;
          baseline_params["offset"] = g.gain * baseline_params.value("offset", 0.0) + g.offset;
          f.baseline_refit = baseline_params;
          f.baseline_refit["refit"] = "gain and offset only";
        }
      }
    }
    result.findings.push_back(std::move(f));
    before = frame_sse(data, r);
  }
  result.final_heldout_rms = result.findings.empty() ? result.heldout_rms : result.findings.back().heldout_rms_after;
  report("unexplained", 0, 1);
  result.unexplained = find_unexplained(data, r, blocks, result.noise_floor_rms);
  if (views) views->after = std::move(r);
  return result;
}

}  // namespace bolo::diag
