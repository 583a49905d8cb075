#pragma once
// What the studies of `validate guidance` share (validate/src/guidance/*.cpp, one file a
// study; the list of studies is in ../guidance.cpp): constants, synthetic particles, the
// explant and default-scene runs at a numerical resolution, and the resolution ladders.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <utility>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/estimate.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/core/sensing.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/stencil.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/steering.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/stats.hpp"
#include "axonguide/validate/validate.hpp"


namespace axg::validate::guidance {

using core::Vec3;

constexpr double kPi = 3.141592653589793;
constexpr double kRadius = 0.5;  // sensing radius r (the scene default)
constexpr double kWidth = 0.1;   // growth-cone width w (the scene default)
constexpr double kAlpha = 0.01;  // family-wise error rate of every check family
inline const double kVolume = 4.0 / 3.0 * kPi * kRadius * kRadius * kRadius;

inline double phi(double x) { return gsl_cdf_ugaussian_P(x); }
inline double z_bound(double tests) { return -gsl_cdf_ugaussian_Pinv(kAlpha / (2.0 * tests)); }

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

inline Vec3 perp_unit(Vec3 v, Vec3 h) {
  const Vec3 p = v - core::dot(h, v) * h;
  const double n = core::norm(p);
  return n > 0.0 ? p / n : Vec3{0, 0, 0};
}

struct MeanSe {
  double mean = 0, se = 0;
};
inline MeanSe mean_se(const std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
  double ss = 0;
  for (double x : v) ss += (x - m) * (x - m);
  return {m, n > 1 ? std::sqrt(ss / (n - 1) / n) : 0.0};
}

// ---- synthetic particles in the particle estimate's two half meshes ----------------------

// A local mesh of 8 nodes per axis at spacing h (nodes at -3.5h ... 3.5h), a tip uniform in
// its central cell, and Poisson particles of intensity (C0 / a)(1 + b (y - tip).x) in the
// cube [-3.5h, 3.5h]^3 (which holds every particle whose deposit reaches the nodes the
// sample at the tip reads), deposited by core::cic_deposit into the half of their id's
// parity, one frame (the moving average's first step: the deposit itself).
struct HalfMeshes {
  double h = 0.5;
  std::vector<std::uint64_t> q;
  std::vector<double> c;
  core::EstimateSet view{};
};

constexpr int kLocalNodes = 8;

inline Vec3 draw_estimate(double c0, double a, double b, std::uint64_t id, std::uint32_t test, HalfMeshes& m) {
  core::Rng rng(71, core::Stream::kValidation, id, test);
  const double h = m.h, half = 3.5 * h;
  const Vec3 tip{h * (rng.uniform() - 0.5), h * (rng.uniform() - 0.5), h * (rng.uniform() - 0.5)};
  const std::size_t nodes = static_cast<std::size_t>(kLocalNodes) * kLocalNodes * kLocalNodes;
  m.q.assign(2 * nodes, 0);
  const Vec3 origin{-half, -half, -half};
  const double lmax = c0 / a * (1.0 + std::fabs(b) * 2.0 * half);
  const double rate = lmax * 8.0 * half * half * half;  // expected points in the cube before thinning
  double t = -std::log(rng.uniform()) / rate;
  std::uint64_t pid = 0;
  while (t < 1.0) {
    const Vec3 y{half * rng.symmetric(), half * rng.symmetric(), half * rng.symmetric()};
    const double accept = (1.0 + b * (y.x - tip.x)) / (1.0 + std::fabs(b) * 2.0 * half);
    if (b == 0.0 || rng.uniform() < accept) {
      const core::CicDeposit d = core::cic_deposit(y, origin, h, kLocalNodes);
      std::uint64_t* q = m.q.data() + static_cast<std::size_t>(core::estimate_half_of(pid)) * nodes;
      for (int k = 0; k < 8; ++k) q[d.index[k]] += d.weight[k];
      ++pid;
    }
    t += -std::log(rng.uniform()) / rate;
  }
  const core::EstimateFold f = core::estimate_fold(1, 1.0, 2.0 * a / (h * h * h * core::kDepositUnit));
  m.c.resize(2 * nodes);
  for (std::size_t i = 0; i < m.c.size(); ++i) m.c[i] = core::fold_node(0.0, m.q[i], f);
  m.view = core::EstimateSet{};
  m.view.h = h, m.view.n = kLocalNodes, m.view.nodes = nodes, m.view.c = m.c.data(), m.view.origin[0] = origin;
  return tip;
}

inline core::CueParams cue_with(double kd) {
  core::CueParams c{};
  c.sign = 1.0;
  c.kd = kd;
  c.min_c = 0.0;
  c.max_c = HUGE_VAL;
  return c;
}

// The growth cone's parameters for the synthetic decisions: the scene defaults' r and w,
// the particle estimate, and molecule amount m.
inline core::SenseParams sense_with(double molecule) {
  Scene s;
  s.cues.field = FieldKind::kParticles;
  s.cues.molecule_amount = molecule;
  s.guidance.sensing_radius = kRadius;
  s.guidance.growth_cone_width = kWidth;
  return sense_params(s);
}

// ---- runs: the explant and the default scene at a numerical resolution --------------------

// A numerical resolution of a field: the particle amount (the emission scales as 1/amount, so
// the source and its field stay the same), or the grid spacing and sub-steps.
struct Resolution {
  FieldKind field = FieldKind::kAnalytic;
  GridScheme scheme = GridScheme::kImplicit;
  double amount = 0.0;          // particles: a (0: the scene's)
  double spacing = 0.0;         // grid: h (0: the scene's default rule)
  std::uint32_t substeps = 0;   // grid: sub-steps (0: the scene's default)
  std::string method() const {
    if (field == FieldKind::kParticles) return "particles";
    if (field == FieldKind::kGrid) return scheme == GridScheme::kExplicit ? "grid explicit" : "grid implicit";
    return "analytic";
  }
  std::string label() const {
    if (field == FieldKind::kParticles) return fmt::format("a = {}", amount);
    if (field == FieldKind::kGrid)
      return substeps ? fmt::format("h = {}, {} sub-steps", spacing, substeps) : fmt::format("h = {}", spacing);
    return "exact";
  }
};

inline void apply(const Resolution& res, Scene& s, double source_strength, std::uint32_t warmup) {
  s.cues.field = res.field;
  if (res.field == FieldKind::kParticles) {
    s.cues.particles.amount = res.amount;
    for (Source& src : s.cues.sources) src.emission = source_strength / res.amount;
  } else {
    // The same a Q for the grid and analytic fields as for the particles.
    for (Source& src : s.cues.sources) src.emission = source_strength / s.cues.particles.amount;
  }
  if (res.field == FieldKind::kGrid) {
    s.cues.grid.scheme = res.scheme;
    if (res.spacing > 0) s.cues.grid.spacing = res.spacing;
    if (res.substeps) s.cues.grid.substeps = res.substeps;
  }
  s.cues.warmup_steps = res.field == FieldKind::kParticles || res.field == FieldKind::kGrid ? warmup : 0;
}

// The explant of B(ii) before: 400 neurons in a ball of radius 1, one attractant 4 LU away
// (a Q = 2 per step, D = 0.5, k = 0.05, K_d = 0.5), no wandering, 30 steps of 0.2 LU, the
// fields warmed up 100 steps (5 particle lifetimes, 33 diffusion times to the explant) so
// that they start at the analytic field's steady state; bounds 12 LU, so that the grids'
// absorbing faces and the particles' deaths at the edge stay 8 LU from the source.
constexpr double kExplantStrength = 2.0;  // a Q per step
// The grids' level 0 on the explant: min(r, lambda / 4) with lambda = 3.2 LU, r = 0.5 LU.
constexpr double kExplantGridSpacing = 0.5;
inline const Vec3 kExplantSource{4, 0, 0};

inline Scene explant_scene(std::uint64_t seed, core::NoiseForm noise, const Resolution& res) {
  Scene s = explant_base(seed, noise);
  apply(res, s, kExplantStrength, 100);
  return s;
}

struct Timed {
  RunResult result;
  double seconds;
};

inline Timed timed_run(const Scene& s) {
  RunOptions ro;
  const auto t0 = std::chrono::steady_clock::now();
  RunResult res = run_scene(s, ro);
  return {std::move(res), seconds_since(t0)};
}

// cos(angle between tip - soma and source - soma) for every neuron.
inline std::vector<double> explant_cosines(const RunResult& res) {
  std::vector<double> out(res.soma.size());
  for (std::size_t i = 0; i < res.soma.size(); ++i) {
    const Vec3 a = res.neurons.tip[i] - res.soma[i], b = kExplantSource - res.soma[i];
    out[i] = core::dot(a, b) / (core::norm(a) * core::norm(b));
  }
  return out;
}

// The guidance index of a resolution against the analytic field, paired by seed (the same
// somas, headings and decision streams). SEs: the larger of the pooled per-axon SE and the
// SE over the seeds' means (the axons of one seed share one particle field).
struct Paired {
  MeanSe index, gap;
  double seconds = 0;  // per run
};

inline MeanSe clustered(const std::vector<std::vector<double>>& per_seed) {
  std::vector<double> all, means;
  for (const auto& v : per_seed) {
    all.insert(all.end(), v.begin(), v.end());
    means.push_back(mean_se(v).mean);
  }
  MeanSe m = mean_se(all);
  if (means.size() > 1) m.se = std::max(m.se, mean_se(means).se);
  return m;
}

class AnalyticCache {
 public:
  const std::vector<double>& get(core::NoiseForm noise, std::uint64_t seed, double* seconds) {
    const auto key = std::make_pair(static_cast<int>(noise), seed);
    auto it = cache_.find(key);
    if (it == cache_.end()) {
      const Timed t = timed_run(explant_scene(seed, noise, Resolution{}));
      it = cache_.emplace(key, std::make_pair(explant_cosines(t.result), t.seconds)).first;
    }
    if (seconds) *seconds = it->second.second;
    return it->second.first;
  }

 private:
  std::map<std::pair<int, std::uint64_t>, std::pair<std::vector<double>, double>> cache_;
};

inline Paired explant_point(const Resolution& res, core::NoiseForm noise, int seeds, AnalyticCache& analytic) {
  std::vector<std::vector<double>> idx, gap;
  double secs = 0;
  for (int sd = 1; sd <= seeds; ++sd) {
    const auto seed = static_cast<std::uint64_t>(sd);
    const std::vector<double>& ref = analytic.get(noise, seed, nullptr);
    std::vector<double> v;
    if (res.field == FieldKind::kAnalytic) {
      v = ref;
    } else {
      const Timed t = timed_run(explant_scene(seed, noise, res));
      v = explant_cosines(t.result);
      secs += t.seconds;
    }
    std::vector<double> d(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) d[i] = v[i] - ref[i];
    idx.push_back(std::move(v));
    gap.push_back(std::move(d));
  }
  return {clustered(idx), clustered(gap), secs / seeds};
}

inline const char* noise_name(core::NoiseForm f) { return name_of(f); }

// ---- C. the explant: every field converges to the analytic field's guidance ---------------

// Ladders of resolution around each field's default (level 0): particles a x {4, 2, 1, 1/2,
// 1/4}; grids h x {4, 2, 1, 1/2} with the implicit scheme's sub-steps doubled at the finest
// level (its splitting error falls with the sub-step, not with h). --quick drops the finer
// levels.
struct Level {
  Resolution res;
  int level;  // 0: the default; negative coarser, positive finer
};

inline std::vector<Level> ladder(FieldKind field, GridScheme scheme, double default_amount, double default_h, bool quick) {
  std::vector<Level> out;
  if (field == FieldKind::kParticles) {
    const int lo = -2, hi = quick ? 0 : 2;
    for (int l = lo; l <= hi; ++l) {
      Resolution r;
      r.field = field;
      r.amount = default_amount * std::pow(2.0, -l);
      out.push_back({r, l});
    }
    return out;
  }
  const int hi = quick ? 0 : 1;
  for (int l = -2; l <= hi; ++l) {
    Resolution r;
    r.field = field;
    r.scheme = scheme;
    r.spacing = default_h * std::pow(2.0, -l);
    if (scheme == GridScheme::kImplicit && l > 0) r.substeps = 1u << l;
    out.push_back({r, l});
  }
  return out;
}

// The grid's evidence at probes around the explant against the analytic field's: the SNR
// forms' evidence alpha w |grad C| f(gamma) / C and the count form's SNR |grad C| r
// sqrt(V / (5 m C)), relative RMS error over probes on spheres of radius 1.5, 2.5, 3.5 about
// the source on the explant's side (x <= 4, at least 8 LU from the grids' faces). The grid
// starts from zero and runs 100 steps, as in the runs. Deterministic: its order in h is exact.
struct EvidenceError {
  double binding = 0, count = 0, seconds = 0;
};

inline EvidenceError evidence_error(const Resolution& res) {
  Scene s = explant_scene(1, core::NoiseForm::kBinding, res);
  const auto cues = make_cues(s);
  auto field = make_reference_field(s, cues);
  PhaseTimes times;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::uint32_t step = 1; step <= s.cues.warmup_steps; ++step) field->advance(step, times);
  EvidenceError e;
  e.seconds = seconds_since(t0);
  const core::SenseParams sp = sense_params(s);
  const core::SteerParams p = steer_params(s);
  std::size_t n = 0;
  for (double radius : {1.5, 2.5, 3.5})
    for (int i = 0; i < 64; ++i) {
      core::Rng rng(79, core::Stream::kValidation, static_cast<std::uint64_t>(i), 103);
      Vec3 d = core::direction_trig(rng);
      if (d.x > 0) d.x = -d.x;
      const Vec3 x = kExplantSource + radius * d;
      core::CueSample got[core::kMaxCues];
      Vec3 pull[core::kMaxCues];
      field->sample(x, got, pull);
      const core::CueSample ref = core::analytic_sample(x, cues[0], sp);
      auto binding = [&](const core::CueSample& c) {
        return p.gain * sp.cone_width * core::norm(c.grad) / c.c * core::snr_occupancy(c.c / cues[0].kd);
      };
      auto count = [&](const core::CueSample& c) { return core::snr_count(c.c, core::norm(c.grad), sp.molecule, sp.radius); };
      const double eb = binding(got[0]) / binding(ref) - 1.0, ec = count(got[0]) / count(ref) - 1.0;
      e.binding += eb * eb, e.count += ec * ec;
      ++n;
    }
  e.binding = std::sqrt(e.binding / n), e.count = std::sqrt(e.count / n);
  return e;
}

struct ExplantRow {
  std::string form, method, label;
  int level;
  double resolution;  // a or h
  Paired p;
  double evidence = NAN;  // grids: relative evidence error of this form
};

struct ExplantStudy {
  std::vector<ExplantRow> rows;
  std::vector<std::vector<std::string>> evidence;
  std::map<std::string, Fit> evidence_fits;  // method + form
  std::vector<std::vector<std::string>> analytic_by_seeds;  // the analytic index's statistical error
};

inline const std::vector<core::NoiseForm> kForms{core::NoiseForm::kCount, core::NoiseForm::kBinding, core::NoiseForm::kSnapshot};
// ---- E, F. the default scene ---------------------------------------------------------------

// A network's guidance and connection metrics. guidance: for every neuron the mean over cues
// of sign_k cos(tip - soma, p_k - soma); connections: the (source, target) pairs.
struct Network {
  std::vector<double> guidance, connected, length;  // per neuron; length of connected axons only
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  double seconds = 0;
};

inline Network network_of(const Timed& t) {
  Network n;
  const RunResult& res = t.result;
  n.seconds = t.seconds;
  for (std::size_t i = 0; i < res.soma.size(); ++i) {
    const Vec3 d = res.neurons.tip[i] - res.soma[i];
    double g = 0;
    for (const core::CueParams& c : res.cues) {
      const Vec3 to = c.position - res.soma[i];
      g += c.sign * core::dot(d, to) / (core::norm(d) * core::norm(to));
    }
    n.guidance.push_back(g / static_cast<double>(res.cues.size()));
    const bool conn = res.neurons.status[i] == core::AxonStatus::kConnected;
    n.connected.push_back(conn ? 1.0 : 0.0);
    if (conn) {
      n.length.push_back(res.neurons.length[i]);
      n.edges.insert({static_cast<std::uint32_t>(i), res.neurons.target[i]});
    }
  }
  return n;
}

inline Scene default_scene_at(std::uint64_t seed, const Resolution& res) {
  Scene s = Scene::builtin_default();
  s.seed = seed;
  const double strength = s.cues.particles.amount * s.cues.sources[0].emission;  // a Q, the same for every source
  apply(res, s, strength, s.cues.warmup_steps);
  return s;
}

inline double jaccard_distance(const Network& a, const Network& b) {
  std::size_t both = 0;
  for (const auto& e : a.edges) both += b.edges.count(e);
  const std::size_t any = a.edges.size() + b.edges.size() - both;
  return any ? 1.0 - static_cast<double>(both) / static_cast<double>(any) : 0.0;
}


// The studies, in the order validate_guidance runs them.
void flat_field(const Options& o, Report& r);
void decision_convergence(const Options& o, Report& r);
void explant(const Options& o, Report& r, AnalyticCache& analytic, ExplantStudy& st);
void molecules(const Options& o, Report& r, AnalyticCache&);
void dipole_correlation(const Options& o, Report& r);
void default_scene(const Options& o, Report& r);
void work_precision(const Options& o, Report& r, const ExplantStudy& explant_st);
void persistence(const Options& o, Report& r);

}  // namespace axg::validate::guidance
