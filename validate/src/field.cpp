// `validate field`: error against run time for the cue fields. One attractant at the
// origin (D = k = 0.05 per step, so lambda = 1 LU) in a domain of radius 6; errors are
// measured at fixed probe points against the analytic steady state (§2.5).
//  - particles: emission Q in {10, 40, 160, 640} with the amount per particle scaled by
//    1/Q (the same concentration), one snapshot after 200 steps; the estimator at each
//    probe is compared with the analytic field averaged the same way over the sensing ball
//    (so the comparison measures Monte-Carlo error, expected to fall as N^(-1/2));
//  - grids: spacing h in {0.4, 0.2, 0.1}; explicit (sub-stepped), implicit LOD at dt = 1,
//    implicit LOD at fixed lambda = D dt/h^2 = 1/2, and the unsplit implicit steady state
//    (k - D L_h) c = s solved with Eigen's conjugate gradients, which separates the grid
//    error (unsplit vs analytic) from the LOD splitting error (LOD vs unsplit).
#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/core/sensing.hpp"
#include "axonguide/core/stencil.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

using core::Vec3;

constexpr double kDomain = 6.0;
constexpr double kProbeRadii[] = {1.0, 1.5, 2.0};
constexpr int kProbesPerRadius = 64;

Scene source_scene(double emission, double amount) {
  Scene s;
  s.neurons.radius = kDomain;
  s.guidance.model = GuidanceModel::kSnr;
  s.guidance.sensing_radius = 0.3;
  // The fields are checked at points: C and grad C at the tip (binding reads them there; the
  // count form's ball average is checked in validate guidance).
  s.guidance.noise = NoiseForm::kBinding;
  s.cues.field = FieldKind::kParticles;
  Source src;
  src.position = Vec3{0, 0, 0};
  src.emission = emission;
  src.diffusion = 0.05;
  src.decay = 0.05;
  s.cues.sources = {src};
  s.cues.particles.amount = amount;
  return s;
}

std::vector<Vec3> probes() {
  std::vector<Vec3> p;
  for (double r : kProbeRadii)
    for (int i = 0; i < kProbesPerRadius; ++i) {
      core::Rng rng(77, core::Stream::kValidation, static_cast<std::uint64_t>(i), 100);
      p.push_back(r * core::direction_trig(rng));
    }
  return p;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Error {
  double c = 0, grad = 0;  // relative RMS errors over the probes
};

// RMS relative errors of samples against references.
Error rms_error(const std::vector<core::CueSample>& got, const std::vector<core::CueSample>& ref) {
  double ec = 0, eg = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const double dc = (got[i].c - ref[i].c) / ref[i].c;
    const double dg = core::norm(got[i].grad - ref[i].grad) / core::norm(ref[i].grad);
    ec += dc * dc;
    eg += dg * dg;
  }
  return {std::sqrt(ec / got.size()), std::sqrt(eg / got.size())};
}

struct Row {
  std::string method;
  double size;  // mean particle count, or h
  double dt;
  Error err;
  double seconds;
  std::string note;
};

std::vector<core::CueSample> field_at(const CueField& f, const std::vector<Vec3>& pts) {
  std::vector<core::CueSample> out;
  for (const Vec3& p : pts) {
    core::CueSample samples[core::kMaxCues];
    Vec3 pull[core::kMaxCues];
    f.sample(p, samples, pull);
    out.push_back(samples[0]);
  }
  return out;
}

// The exact expectation of the particle field of one source at the origin after field step
// t (SPEC §3.3): a particle emitted at step s has moved t - s + 1 Brownian steps of
// per-axis variance 2 D dt and survived as many draws of probability p = e^(-k dt), so
//   E C(x, t) = a Q sum_{m=1}^{t} p^m G(x; 2 D dt m),  grad = -a Q sum p^m G x / (2 D dt m)
// (G: the 3D Gaussian density). Deaths at the domain's edge (radius 6, probes within 2.5)
// are left out: they change it by less than e^-30 here.
core::CueSample particle_expectation(Vec3 x, std::uint32_t t, double aq, double d, double k, double dt) {
  const double r2 = core::norm2(x);
  double c = 0, g = 0;
  for (std::uint32_t m = 1; m <= t; ++m) {
    const double v = 2.0 * d * dt * m;
    const double term = std::exp(-k * dt * m) * std::exp(-r2 / (2.0 * v)) / std::pow(2.0 * 3.141592653589793 * v, 1.5);
    c += term;
    g += term / v;
    if (m > 50 && term < 1e-18 * c) break;
  }
  return {aq * c, (-aq * g) * x, {0, 0, 0}};
}

// The estimate of one source's field at the probes, every step of [first, last].
struct EstimateRun {
  std::vector<std::vector<core::CueSample>> samples;  // [step][probe]
  double seconds = 0;
  double particles = 0;
};

EstimateRun run_estimate(Scene s, std::uint32_t first, std::uint32_t last, const std::vector<Vec3>& pts) {
  const auto cues = make_cues(s);
  auto field = make_reference_field(s, cues);
  PhaseTimes times;
  EstimateRun out;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::uint32_t step = 1; step <= last; ++step) {
    field->advance(step, times);
    if (step >= first) {
      out.samples.push_back(field_at(*field, pts));
      out.particles += static_cast<double>(field->particles());
    }
  }
  out.seconds = seconds_since(t0);
  out.particles /= static_cast<double>(out.samples.size());
  return out;
}

// Relative errors of the estimate against the exact expectation, for C and the radial
// gradient: per probe, the mean over the sampled steps (its systematic error) and the
// variance over them (its noise, which the moving average correlates but does not bias).
//   bias:    the mean over probes and radii of the per-probe means;
//   spatial: the RMS over probes of the per-probe means (the bias and its pattern over
//            the probes' places in the mesh: the whole systematic error), less the noise
//            that remains in those means (batch means over blocks of `batch` steps);
//   noise:   the square root of the mean per-probe variance.
struct EstimateError {
  double bias_c = 0, bias_g = 0, bias_c_se = 0, bias_g_se = 0, spatial_c = 0, spatial_g = 0, noise_c = 0, noise_g = 0;
};

EstimateError estimate_error(const EstimateRun& run, const std::vector<Vec3>& pts,
                             const std::vector<core::CueSample>& exact, std::size_t batch) {
  EstimateError e;
  const std::size_t steps = run.samples.size(), n = pts.size();
  std::vector<double> mc(n), mg(n);
  for (std::size_t q = 0; q < n; ++q) {
    const Vec3 u = pts[q] / core::norm(pts[q]);
    const double g_ref = core::dot(exact[q].grad, u);
    double sc = 0, sg = 0, sc2 = 0, sg2 = 0;
    for (std::size_t t = 0; t < steps; ++t) {
      const core::CueSample& got = run.samples[t][q];
      const double dc = (got.c - exact[q].c) / exact[q].c;
      const double dg = (core::dot(0.5 * (got.grad + got.grad_check), u) - g_ref) / g_ref;
      sc += dc, sg += dg, sc2 += dc * dc, sg2 += dg * dg;
    }
    const double m = static_cast<double>(steps);
    mc[q] = sc / m, mg[q] = sg / m;
    if (steps > 1) {
      e.noise_c += (sc2 - m * mc[q] * mc[q]) / (m - 1) / n;
      e.noise_g += (sg2 - m * mg[q] * mg[q]) / (m - 1) / n;
    }
    // The noise left in the per-probe means, from batch means over blocks of `batch` steps
    // (longer than the moving average's correlation), is taken out of the systematic error.
    double vmc = 0, vmg = 0;
    const std::size_t batches = batch > 0 ? steps / batch : 0;
    if (batches > 1) {
      for (std::size_t bi = 0; bi < batches; ++bi) {
        double bc = 0, bg = 0;
        for (std::size_t t = bi * batch; t < (bi + 1) * batch; ++t) {
          const core::CueSample& got = run.samples[t][q];
          bc += (got.c - exact[q].c) / exact[q].c;
          bg += (core::dot(0.5 * (got.grad + got.grad_check), u) - g_ref) / g_ref;
        }
        bc = bc / batch - mc[q], bg = bg / batch - mg[q];
        vmc += bc * bc, vmg += bg * bg;
      }
      vmc /= static_cast<double>(batches - 1) * batches, vmg /= static_cast<double>(batches - 1) * batches;
    }
    e.bias_c += mc[q] / n, e.bias_g += mg[q] / n;
    e.spatial_c += (mc[q] * mc[q] - vmc) / n, e.spatial_g += (mg[q] * mg[q] - vmg) / n;
  }
  double vc = 0, vg = 0;
  for (std::size_t q = 0; q < n; ++q) vc += (mc[q] - e.bias_c) * (mc[q] - e.bias_c), vg += (mg[q] - e.bias_g) * (mg[q] - e.bias_g);
  e.bias_c_se = std::sqrt(vc / (n - 1) / n), e.bias_g_se = std::sqrt(vg / (n - 1) / n);
  e.spatial_c = std::sqrt(std::max(0.0, e.spatial_c)), e.spatial_g = std::sqrt(std::max(0.0, e.spatial_g));
  e.noise_c = std::sqrt(std::max(0.0, e.noise_c)), e.noise_g = std::sqrt(std::max(0.0, e.noise_g));
  return e;
}

struct EstimateStudy {
  std::vector<std::vector<std::string>> noise, bias, lag;
  std::vector<Fit> noise_fit, bias_fit, lag_fit;  // C, grad
  double lag_worst_z = 0;  // largest |measured - predicted| / (3 SE + 0.1 |predicted|) of the C lag
  std::vector<struct Row> rows;
};

// The estimator's scene: one source at the origin with D = 0.5, k = 0.05 (lambda = 3.2 LU,
// the explant's source) and a Q = 1 per step, in a domain of radius 12 so that deaths at
// its edge do not reach the probes at r = 2, 3, 4.
constexpr double kEstD = 0.5, kEstK = 0.05;
constexpr double kEstRadii[] = {2.0, 3.0, 4.0};

Scene estimate_scene(double emission, double spacing, double tau) {
  Scene s = source_scene(emission, 1.0 / emission);
  s.neurons.radius = 12.0;
  s.cues.sources[0].diffusion = kEstD;
  s.cues.sources[0].decay = kEstK;
  s.cues.particles.estimate.spacing = spacing;
  s.cues.particles.estimate.time = tau;
  return s;
}

std::vector<Vec3> estimate_probes() {
  std::vector<Vec3> p;
  for (double r : kEstRadii)
    for (int i = 0; i < kProbesPerRadius; ++i) {
      core::Rng rng(78, core::Stream::kValidation, static_cast<std::uint64_t>(i), 102);
      p.push_back(r * core::direction_trig(rng));
    }
  return p;
}

std::vector<core::CueSample> exact_at(const std::vector<Vec3>& pts, std::uint32_t t) {
  std::vector<core::CueSample> out;
  for (const Vec3& p : pts) out.push_back(particle_expectation(p, t, 1.0, kEstD, kEstK, 1.0));
  return out;
}

// The particle field's estimate (core/estimate.hpp) against the exact expectation of the
// particles: (i) its noise against the amount per particle at the default mesh and moving
// average, (ii) its systematic error against the mesh spacing with many particles, (iii) the
// lag of its moving average in a field that is still building up, against the time constant.
EstimateStudy estimate_study(const Options& o) {
  EstimateStudy st;
  const std::vector<Vec3> pts = estimate_probes();
  constexpr std::uint32_t kSteady = 150, kSamples = 200;
  const std::vector<core::CueSample> steady = exact_at(pts, 4000);
  // (i) noise at the default mesh spacing and time constant (the sensing radius 0.5, 10 steps)
  std::vector<double> emissions{25, 100, 400, 1600};
  if (o.quick) emissions.pop_back();
  std::vector<double> la, lnc, lng;
  for (double q : emissions) {
    const EstimateRun run = run_estimate(estimate_scene(q, 0.5, 10.0), kSteady + 1, kSteady + kSamples, pts);
    const EstimateError e = estimate_error(run, pts, steady, 40);
    st.noise.push_back({num(1.0 / q), num(run.particles, 6), num(e.noise_c), num(e.noise_g), num(e.spatial_c),
                        num(e.spatial_g), num(run.seconds)});
    la.push_back(std::log(1.0 / q)), lnc.push_back(std::log(e.noise_c)), lng.push_back(std::log(e.noise_g));
    st.rows.push_back({"particles (estimate h = 0.5, tau = 10)", run.particles, 1.0,
                       Error{std::hypot(e.spatial_c, e.noise_c), std::hypot(e.spatial_g, e.noise_g)}, run.seconds,
                       fmt::format("a = 1/{}", q)});
  }
  st.noise_fit = {fit_line(la, lnc), fit_line(la, lng)};
  // (ii) systematic error against h
  std::vector<double> spacings{1.4, 1.0, 0.7, 0.5};
  if (o.quick) spacings.pop_back();
  const double q_bias = o.quick ? 3200 : 6400;
  std::vector<double> lh, lbc, lbg;
  for (double h : spacings) {
    const EstimateRun run = run_estimate(estimate_scene(q_bias, h, 10.0), kSteady + 1, kSteady + kSamples, pts);
    const EstimateError e = estimate_error(run, pts, steady, 40);
    st.bias.push_back({num(h), num(e.bias_c), num(e.bias_c_se, 2), num(e.spatial_c), num(e.bias_g), num(e.bias_g_se, 2),
                       num(e.spatial_g), num(e.noise_c), num(run.seconds)});
    lh.push_back(std::log(h)), lbc.push_back(std::log(e.spatial_c)), lbg.push_back(std::log(e.spatial_g));
  }
  st.bias_fit = {fit_line(lh, lbc), fit_line(lh, lbg)};
  // (iii) lag: the field at step 10 of its build-up, over several seeds; the lag is the error
  // at time constant tau less that at tau = 0 (the same particles and mesh, this step only),
  // paired per probe and seed, against the moving average's own prediction
  // sum_s w_s C(s) / C(t) - 1 from the exact expectation.
  constexpr std::uint32_t kT = 10;
  const int seeds = o.quick ? 2 : 4;
  const double q_lag = 51200;
  const std::vector<core::CueSample> at_t = exact_at(pts, kT);
  const std::vector<double> taus{0.5, 1, 2};
  auto errors_at = [&](double tau) {
    std::vector<double> dc, dg;
    double secs = 0;
    for (int sd = 1; sd <= seeds; ++sd) {
      Scene sc = estimate_scene(q_lag, 0.5, tau);
      sc.seed = static_cast<std::uint64_t>(sd);
      const EstimateRun run = run_estimate(sc, kT, kT, pts);
      secs += run.seconds;
      for (std::size_t q = 0; q < pts.size(); ++q) {
        const Vec3 u = pts[q] / core::norm(pts[q]);
        const double g_ref = core::dot(at_t[q].grad, u);
        const core::CueSample& got = run.samples[0][q];
        dc.push_back((got.c - at_t[q].c) / at_t[q].c);
        dg.push_back((core::dot(0.5 * (got.grad + got.grad_check), u) - g_ref) / g_ref);
      }
    }
    return std::make_tuple(dc, dg, secs);
  };
  const auto [base_c, base_g, base_secs] = errors_at(0.0);
  std::vector<double> lt, llc, llg;
  for (double tau : taus) {
    const auto [dc, dg, secs] = errors_at(tau);
    double lc = 0, lg = 0, lc2 = 0;
    const double n = static_cast<double>(dc.size());
    for (std::size_t j = 0; j < dc.size(); ++j) {
      const double d = dc[j] - base_c[j];
      lc += d, lc2 += d * d, lg += dg[j] - base_g[j];
    }
    lc /= n, lg /= n;
    const double lc_se = std::sqrt(std::max(0.0, lc2 / n - lc * lc) / (n - 1));
    const EstimateParams ep = estimate_params(estimate_scene(q_lag, 0.5, tau));
    double pred = 0;
    for (double radius : kEstRadii) {
      const Vec3 x{radius, 0, 0};
      const double ct = particle_expectation(x, kT, 1.0, kEstD, kEstK, 1.0).c;
      double acc = 0, wsum = 0;
      for (std::uint32_t sidx = 1; sidx <= kT; ++sidx) {
        const double w = ep.beta * std::pow(1.0 - ep.beta, static_cast<double>(kT - sidx));
        acc += w * particle_expectation(x, sidx, 1.0, kEstD, kEstK, 1.0).c;
        wsum += w;
      }
      pred += (acc / wsum / ct - 1.0) / static_cast<double>(std::size(kEstRadii));
    }
    // The moving average's mean age in steps, (1 - beta) / beta = tau/dt - 1/2 + O(dt/tau): the
    // lag of a field rising smoothly is proportional to it.
    const double age = (1.0 - ep.beta) / ep.beta;
    st.lag.push_back({num(tau), num(age), num(lc), num(lc_se, 2), num(pred), num(lg), num(secs + base_secs)});
    lt.push_back(std::log(age)), llc.push_back(std::log(std::fabs(lc))), llg.push_back(std::log(std::fabs(lg)));
    // Within 3 SE and 10 % of the prediction (the prediction leaves out the mesh's smoothing).
    st.lag_worst_z = std::max(st.lag_worst_z, std::fabs(lc - pred) / (3.0 * lc_se + 0.1 * std::fabs(pred)));
  }
  st.lag_fit = {fit_line(lt, llc), fit_line(lt, llg)};
  return st;
}

std::vector<core::CueSample> analytic_at(const Scene& s, const std::vector<Vec3>& pts) {
  const auto cues = make_cues(s);
  const auto sp = sense_params(s);
  std::vector<core::CueSample> out;
  for (const Vec3& p : pts) out.push_back(core::analytic_sample(p, cues[0], sp));
  return out;
}


// The steady state of the unsplit semi-discrete problem, (k - D L_h) c = s / dt with
// c = 0 on the faces (absorbing), by preconditioned conjugate gradients (Eigen).
std::vector<double> unsplit_steady_state(const Scene& s, const core::CueParams& cue) {
  const GridGeometry3 g = grid_field_geometry(s);
  const int n = g.n, m = n - 2;  // interior nodes per axis
  const double h2 = g.h * g.h;
  auto interior = [m](int i, int j, int k) {
    return static_cast<Eigen::Index>((static_cast<std::size_t>(k - 1) * m + (j - 1)) * m + (i - 1));
  };
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<std::size_t>(m) * m * m * 7);
  for (int k = 1; k <= m; ++k)
    for (int j = 1; j <= m; ++j)
      for (int i = 1; i <= m; ++i) {
        const Eigen::Index row = interior(i, j, k);
        t.emplace_back(row, row, cue.decay + 6.0 * cue.diffusion / h2);
        const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k}, {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
        for (const auto& q : nb)
          if (q[0] >= 1 && q[0] <= m && q[1] >= 1 && q[1] <= m && q[2] >= 1 && q[2] <= m)
            t.emplace_back(row, interior(q[0], q[1], q[2]), -cue.diffusion / h2);
      }
  Eigen::SparseMatrix<double> a(static_cast<Eigen::Index>(m) * m * m, static_cast<Eigen::Index>(m) * m * m);
  a.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(a.rows());
  const core::SourceDeposit d = core::source_deposit(cue.position, s.cues.particles.amount * cue.emission / s.dt,
                                                     g.origin, g.h, n);
  for (int q = 0; q < 8; ++q) {
    const std::size_t idx = d.index[q];
    const int i = static_cast<int>(idx % n), j = static_cast<int>((idx / n) % n), k = static_cast<int>(idx / (n * n));
    if (i >= 1 && i <= m && j >= 1 && j <= m && k >= 1 && k <= m) rhs[interior(i, j, k)] += d.value[q];
  }
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>>
      cg;
  cg.setTolerance(1e-11);
  cg.setMaxIterations(5000);
  cg.compute(a);
  const Eigen::VectorXd c = cg.solve(rhs);
  std::vector<double> full(g.nodes(), 0.0);
  for (int k = 1; k <= m; ++k)
    for (int j = 1; j <= m; ++j)
      for (int i = 1; i <= m; ++i) full[core::node_index(i, j, k, n)] = c[interior(i, j, k)];
  return full;
}

std::vector<Row> grid_study(const Options& o, std::vector<std::vector<std::string>>& splitting) {
  std::vector<Row> rows;
  const std::vector<Vec3> pts = probes();
  std::vector<double> spacings{0.4, 0.2, 0.1};
  if (o.quick) spacings.pop_back();
  constexpr double kSteadyTime = 250;  // 12.5 relaxation times 1/k
  for (double h : spacings) {
    Scene base = source_scene(100, 0.01);
    base.cues.field = FieldKind::kGrid;
    base.cues.grid.spacing = h;
    const std::vector<core::CueSample> exact = analytic_at(base, pts);
    const GridGeometry3 geometry = grid_field_geometry(base);
    std::vector<core::CueSample> unsplit;
    {
      const auto t0 = std::chrono::steady_clock::now();
      const auto cues = make_cues(base);
      const std::vector<double> c = unsplit_steady_state(base, cues[0]);
      core::GridFieldSet set{geometry.origin, geometry.h, geometry.n, {}};
      set.c[0] = c.data();
      for (const Vec3& p : pts) {
        core::CueSample samples[core::kMaxCues];
        Vec3 pull[core::kMaxCues];
        core::sample_grid_field(p, set, cues.data(), 1, core::SenseParams{}, samples, pull);  // at the point
        unsplit.push_back(samples[0]);
      }
      rows.push_back({"unsplit steady state (Eigen CG)", h, 0, rms_error(unsplit, exact), seconds_since(t0),
                      fmt::format("{}^3 nodes", geometry.n)});
    }
    struct Scheme {
      const char* name;
      GridScheme scheme;
      double dt;
    };
    const double dt_lambda = 0.5 * h * h / 0.05;
    const Scheme schemes[] = {{"explicit (sub-stepped), dt = 1", GridScheme::kExplicit, 1.0},
                              {"implicit LOD, dt = 1", GridScheme::kImplicit, 1.0},
                              {"implicit LOD, lambda = 1/2", GridScheme::kImplicit, dt_lambda}};
    for (const Scheme& sc : schemes) {
      Scene s = base;
      s.cues.grid.scheme = sc.scheme;
      s.dt = sc.dt;
      // Keep the source rate a Q / dt per time unit fixed: Q scales with dt.
      s.cues.sources[0].emission = 100 * sc.dt;
      const auto cues = make_cues(s);
      auto f = make_reference_field(s, cues);
      PhaseTimes times;
      const auto steps = static_cast<std::uint32_t>(std::ceil(kSteadyTime / sc.dt));
      const auto t0 = std::chrono::steady_clock::now();
      for (std::uint32_t step = 1; step <= steps; ++step) f->advance(step, times);
      const double secs = seconds_since(t0);
      const std::vector<core::CueSample> got = field_at(*f, pts);
      rows.push_back({sc.name, h, sc.dt, rms_error(got, exact), secs,
                      sc.scheme == GridScheme::kExplicit ? f->note() : fmt::format("{} steps", steps)});
      const Error split = rms_error(got, unsplit);
      splitting.push_back({sc.name, num(h), num(sc.dt), num(s.cues.sources[0].diffusion * sc.dt / (h * h)),
                           num(split.c), num(split.grad)});
    }
  }
  return rows;
}

}  // namespace

Fit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  const Eigen::Index n = static_cast<Eigen::Index>(x.size());
  Eigen::MatrixXd a(n, 2);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    a(i, 0) = x[static_cast<std::size_t>(i)];
    a(i, 1) = 1.0;
    b[i] = y[static_cast<std::size_t>(i)];
  }
  const Eigen::Vector2d p = a.colPivHouseholderQr().solve(b);
  double se = 0;
  if (n > 2) {
    const Eigen::VectorXd res = b - a * p;
    const double s2 = res.squaredNorm() / static_cast<double>(n - 2);
    const Eigen::Matrix2d cov = s2 * (a.transpose() * a).inverse();
    se = std::sqrt(cov(0, 0));
  }
  return {p[0], p[1], se};
}

void validate_field(const Options& o, Report& r) {
  r.text("One attractant at the origin (D = k = 0.05, so lambda = 1 LU, a Q = 1 per step) in a domain of radius 6 "
         "with absorbing faces. Probes: 64 directions at each of r = 1, 1.5, 2 LU from the source. Errors are "
         "relative, for the concentration C and the gradient: RMS over the probes for the grids (against the "
         "analytic steady state), and split into bias and noise for the particle field's estimate (against the exact "
         "expectation of the particles, particle_expectation in validate/src/field.cpp).");
  EstimateStudy est;
  std::vector<Row> grids;
  std::vector<std::vector<std::string>> splitting;
  with_threads(o.threads, [&] {
    est = estimate_study(o);
    grids = grid_study(o, splitting);
  });
  const std::vector<Row>& particles = est.rows;
  std::vector<std::vector<std::string>> table;
  for (const std::vector<Row>* set : {&particles, static_cast<const std::vector<Row>*>(&grids)})
    for (const Row& row : *set)
      table.push_back({row.method, num(row.size, 6), num(row.dt), num(row.err.c), num(row.err.grad),
                       num(row.seconds), row.note});
  r.heading("Error against run time");
  r.text("`size` is the mean particle count for particles and the spacing h for grids; `seconds` is the wall "
         "time of the field's run (particles: 400 steps, of which the last 200 are sampled; grids: to steady state; "
         "the unsplit solution: the Eigen solve). The particle rows' error is sqrt(bias^2 + noise^2) of the estimate.");
  r.table({"method", "size", "dt", "error_C", "error_grad", "seconds", "note"}, table, "field_errors.csv");

  r.heading("The particle field's estimate: noise, bias and lag");
  r.text("One source at the origin with D = 0.5, k = 0.05 (lambda = 3.2 LU, the explant's source of `validate "
         "guidance`), a Q = 1 per step, in a domain of radius 12; 64 probes at each of r = 2, 3, 4 LU; errors relative "
         "to the exact expectation of the particles, for C and the radial gradient (the mean of both halves' "
         "gradients). Per probe, the mean error over the sampled steps is its systematic error and the variance its "
         "noise. (i) Noise: at mesh spacing h = 0.5 and time constant tau = 10 (the defaults for the explant's sensing "
         "radius), over 200 steps of the steady state, against the amount a per particle (a Q = 1: the same field); a "
         "Monte Carlo estimate's noise falls as a^(1/2). (ii) Systematic error: the RMS over probes of their mean error, "
         "against h, with a = 1/" +
         num(o.quick ? 3200.0 : 6400.0) +
         "; cloud-in-cell deposits and the interpolation smooth the field over about h, so it falls as h^2 (`bias` is "
         "its mean over probes, SE from their spread). (iii) Lag: at step 10 of the build-up (C still rising), the bias "
         "at time constant tau less the bias at tau = 0 (the same particles and mesh, this step only; paired per probe), "
         "with a = 1/51200, over " +
         std::to_string(o.quick ? 2 : 4) +
         " seeds, against the moving average's own prediction sum_s w_s C(s) / C(t) - 1 from the exact expectation. "
         "It grows as the mean age of the average, (1 - beta) / beta = tau/dt - 1/2 + O(dt/tau) steps (beta = 1 - "
         "e^(-dt/tau)), so as tau once tau >> dt. In a steady field there is no lag.");
  r.table({"a", "particles", "noise C", "noise grad", "systematic C", "systematic grad", "seconds"}, est.noise,
          "estimate_noise.csv");
  r.table({"h", "bias C", "bias C SE", "systematic C", "bias grad", "bias grad SE", "systematic grad", "noise C", "seconds"},
          est.bias, "estimate_bias.csv");
  r.table({"tau", "mean age", "lag C", "lag C SE", "predicted lag C", "lag grad", "seconds"}, est.lag, "estimate_lag.csv");
  std::vector<std::vector<std::string>> orders;
  orders.push_back({"particle estimate", "noise of C vs a", num(est.noise_fit[0].slope, 3), num(est.noise_fit[0].slope_se, 2), "1/2"});
  orders.push_back({"particle estimate", "noise of grad C vs a", num(est.noise_fit[1].slope, 3), num(est.noise_fit[1].slope_se, 2), "1/2"});
  orders.push_back({"particle estimate", "systematic error of C vs h", num(est.bias_fit[0].slope, 3), num(est.bias_fit[0].slope_se, 2), "2"});
  orders.push_back({"particle estimate", "systematic error of grad C vs h", num(est.bias_fit[1].slope, 3), num(est.bias_fit[1].slope_se, 2), "2"});
  orders.push_back({"particle estimate", "lag of C vs mean age", num(est.lag_fit[0].slope, 3), num(est.lag_fit[0].slope_se, 2), "1"});
  orders.push_back({"particle estimate", "lag of grad C vs mean age", num(est.lag_fit[1].slope, 3), num(est.lag_fit[1].slope_se, 2), "1"});
  for (int k = 0; k < 2; ++k) {
    const char* what = k == 0 ? "C" : "grad C";
    r.check({fmt::format("particle estimate: order of the noise of {} in the amount", what),
             est.noise_fit[k].slope > 0.4 && est.noise_fit[k].slope < 0.6, num(est.noise_fit[k].slope, 3),
             "slope in [0.4, 0.6] (theory 1/2)", fmt::format("{:+.3f} from 1/2", est.noise_fit[k].slope - 0.5)});
    r.check({fmt::format("particle estimate: order of the systematic error of {} in the mesh spacing", what),
             est.bias_fit[k].slope > 1.5 && est.bias_fit[k].slope < 2.7, num(est.bias_fit[k].slope, 3),
             "slope in [1.5, 2.7] (theory 2)", fmt::format("{:+.3f} from 2", est.bias_fit[k].slope - 2)});
    r.check({fmt::format("particle estimate: order of the lag of {} in the moving average's mean age", what),
             est.lag_fit[k].slope > 0.7 && est.lag_fit[k].slope < 1.3, num(est.lag_fit[k].slope, 3),
             "slope in [0.7, 1.3] (theory 1)", fmt::format("{:+.3f} from 1", est.lag_fit[k].slope - 1)});
  }
  r.check({"particle estimate: the lag of C is the moving average's prediction", est.lag_worst_z < 1.0,
           fmt::format("largest |measured - predicted| / (3 SE + 0.1 |predicted|) = {:.3f}", est.lag_worst_z),
           "below 1", fmt::format("{:.2f} of the bound", est.lag_worst_z)});

  r.heading("Convergence orders");
  auto order_of = [&](const std::vector<Row>& rows, const std::string& method, bool gradient) {
    std::vector<double> x, y;
    for (const Row& row : rows)
      if (row.method == method) {
        x.push_back(std::log(row.size));
        y.push_back(std::log(gradient ? row.err.grad : row.err.c));
      }
    return fit_line(x, y);
  };
  for (const char* m : {"unsplit steady state (Eigen CG)", "explicit (sub-stepped), dt = 1", "implicit LOD, lambda = 1/2",
                        "implicit LOD, dt = 1"}) {
    const Fit c = order_of(grids, m, false), g = order_of(grids, m, true);
    orders.push_back({m, "C vs h", num(c.slope, 3), num(c.slope_se, 2), std::string(m).find("dt = 1") != std::string::npos &&
                                                                               std::string(m).find("LOD") != std::string::npos
                                                                           ? "none (splitting error of about 5 % at dt = 1)"
                                                                           : "2"});
    orders.push_back({m, "grad C vs h", num(g.slope, 3), num(g.slope_se, 2), "2 (interpolated centred differences)"});
    if (std::string(m).find("unsplit") != std::string::npos || std::string(m).find("explicit") != std::string::npos ||
        std::string(m).find("lambda") != std::string::npos)
      r.check({fmt::format("grid, {}: order of the C error in h", m), c.slope > 1.5 && c.slope < 2.7, num(c.slope, 3),
               "slope in [1.5, 2.7] (theory 2)", fmt::format("{:+.3f} from 2", c.slope - 2)});
  }
  r.table({"method", "error", "measured order", "std. error", "expected"}, orders, "field_orders.csv");
  // The explicit scheme's steady state is the discrete steady state: it must equal the
  // unsplit solve up to the solver tolerance.
  for (std::size_t k = 0; k < splitting.size(); ++k)
    if (splitting[k][0].find("explicit") != std::string::npos) {
      const double e = std::stod(splitting[k][4]);
      r.check({"explicit steady state equals the unsplit discrete steady state (h = " + splitting[k][1] + ")", e < 1e-4,
               num(e), "relative RMS difference < 1e-4", fmt::format("{:.2g}x the bound", e / 1e-4)});
    }
  r.heading("LOD splitting error");
  r.text("Difference between each time-stepped steady state and the unsplit steady state on the same grid: "
         "for the explicit scheme it is the solver tolerance; for implicit LOD it is the splitting error, which "
         "grows with the time step: about 5 % at dt = 1 whatever h, and falling as h^2 when dt shrinks with h^2.");
  r.table({"method", "h", "dt", "lambda", "vs unsplit: C", "vs unsplit: grad"}, splitting, "field_splitting.csv");
  r.plot("field_convergence.py", {"field_errors.csv"}, "field_convergence.png",
         "Error of C against resolution: particles against particle count, grids against h (log-log).");
  r.plot("work_precision.py", {"field_errors.csv"}, "work_precision.png",
         "Work-precision: error of C against wall time for every method.");
}

}  // namespace axg::validate
