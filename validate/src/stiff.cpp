// `validate stiff`: the stiff and extreme battery of SPEC §7 as a pass/fail table. Every
// case must finish with finite, non-negative, bounded results, or refuse with a clear
// error; none may blow up silently.
#include <chrono>
#include <cfloat>
#include <cmath>

#include <fmt/format.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "axonguide/core/pmath.hpp"
#include "axonguide/core/signalling.hpp"
#include "axonguide/core/steering.hpp"
#include "axonguide/core/wander.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/model/sensing.hpp"
#include "axonguide/model/signalling.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/fields/fields.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/placement/sampler_nd.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

using core::Vec3;

Scene one_source(FieldKind field, GridScheme scheme, double d, double k, double h) {
  Scene s;
  s.neurons.radius = 2.0;
  s.guidance.model = GuidanceModel::kSnr;
  s.cues.field = field;
  s.cues.grid.scheme = scheme;
  s.cues.grid.spacing = h;
  Source src;
  src.position = Vec3{0.05, -0.03, 0.02};
  src.diffusion = d;
  src.decay = k;
  s.cues.sources = {src};
  return s;
}

struct Scan {
  bool finite = true;
  double min = HUGE_VAL, max = -HUGE_VAL;
};

Scan scan_field(const CueField& f, double half) {
  Scan out;
  for (double x = -half; x <= half; x += half / 7)
    for (double y = -half; y <= half; y += half / 7)
      for (double z = -half; z <= half; z += half / 5) {
        core::CueSample s[core::kMaxCues];
        Vec3 pull[core::kMaxCues];
        f.sample({x, y, z}, s, pull);
        out.finite = out.finite && std::isfinite(s[0].c) && std::isfinite(s[0].grad.x) &&
                     std::isfinite(s[0].grad.y) && std::isfinite(s[0].grad.z);
        out.min = std::min(out.min, s[0].c);
        out.max = std::max(out.max, s[0].c);
      }
  return out;
}

bool unit_and_finite(Vec3 h) {
  return std::isfinite(h.x) && std::isfinite(h.y) && std::isfinite(h.z) && std::fabs(core::norm(h) - 1.0) < 1e-14;
}

// The signalling network's oracle: GSL's adaptive multistep BDF (msbdf) at relative and
// absolute tolerance tol, from y over time t (minutes) at tip concentration c, inhibition i.
struct GslSignalling {
  core::SignallingSystem sys;
};

int gsl_signal_rhs(double, const double y[], double f[], void* p) {
  static_cast<GslSignalling*>(p)->sys.rhs(y, f);
  return GSL_SUCCESS;
}

int gsl_signal_jac(double, const double y[], double* dfdy, double dfdt[], void* p) {
  static_cast<GslSignalling*>(p)->sys.jacobian(y, dfdy);
  for (int i = 0; i < core::kSignalSpecies; ++i) dfdt[i] = 0.0;
  return GSL_SUCCESS;
}

bool signalling_oracle(const core::SignallingParams& q, double c, double i, double* y, double t, double tol) {
  GslSignalling ctx{{&q, c, i}};
  gsl_odeiv2_system sys{gsl_signal_rhs, gsl_signal_jac, static_cast<size_t>(core::kSignalSpecies), &ctx};
  gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_msbdf, 1e-6, tol, tol);
  double t0 = 0;
  const int status = gsl_odeiv2_driver_apply(d, &t0, t, y);
  gsl_odeiv2_driver_free(d);
  return status == GSL_SUCCESS;
}

// Bicknell et al. 2018's Table 1 in /min and nM (the scene defaults).
core::SignallingParams table1_params() {
  Scene s;
  s.units.length = "um";
  s.units.time = "min";
  s.units.concentration = "nM";
  s.axons.growth_model = GrowthModel::kSignalling;
  return signalling_params(s);
}

// The signalling network (core/signalling.hpp, ROS2): its extremes against the oracle, and
// its error against run time.
void validate_signalling(const Options& o, Report& r) {
  const core::SignallingParams base = table1_params();
  auto inhibition = [](const core::SignallingParams& q, double c) { return core::bound_receptors(q.It, q.kpI, q.kmI, c); };
  // One 48 h integration from the cell body's steady state, the tip at ct: ROS2 in `steps`
  // steps against the oracle; the length grown R is the model's output.
  struct Outcome {
    core::StiffStatus status;
    bool in_range;
    double r_ros2, r_oracle, max_rel;
  };
  auto integrate = [&](const core::SignallingParams& q, double cb, double ct, int steps) {
    double y[core::kSignalSpecies], ref[core::kSignalSpecies];
    const double i = inhibition(q, cb);
    core::signalling_steady_state(q, cb, i, y);
    std::copy(y, y + core::kSignalSpecies, ref);
    const core::SignallingStep st = core::signalling_step(q, y, ct, i, 2880.0, steps);
    Outcome out{st.status, true, y[core::kSR], 0.0, 0.0};
    for (int k = 0; k < core::kSignalSpecies; ++k)
      out.in_range = out.in_range && std::isfinite(y[k]) && y[k] >= 0.0 && (k != core::kSF || y[k] <= q.Ft);
    if (!signalling_oracle(q, ct, i, ref, 2880.0, 1e-10)) out.r_oracle = std::nan("");
    else out.r_oracle = ref[core::kSR];
    for (int k = 0; k < core::kSignalSpecies; ++k)
      out.max_rel = std::max(out.max_rel, std::fabs(y[k] - ref[k]) / (std::fabs(ref[k]) + 1e-9 * (1 + std::fabs(ref[k]))));
    return out;
  };
  r.text("The signalling network (docs/methods.md §2.10): 48 h of ROS2 at the scene's step (30 min, 96 steps) "
         "from the cell body's steady state, the tip at 1 to 10 times the cell body's concentration. A case passes "
         "when every species stays finite and in its range (>= 0, F <= F_t) and the length grown R is within 1 % "
         "of GSL's msbdf at tolerance 1e-10.");
  // Concentrations from 1e-6 to 1e4 nM.
  for (double cb : {1e-6, 1e-3, 0.1, 1.0, 1e2, 1e4}) {
    const Outcome e = integrate(base, cb, cb * 1.1, 96);
    const bool ok = e.status == core::StiffStatus::kOk && e.in_range && std::fabs(e.r_ros2 - e.r_oracle) <= 0.01 * e.r_oracle;
    r.check({fmt::format("signalling at C = {} nM (tip 1.1x)", num(cb)), ok,
             fmt::format("R = {} um, oracle {} um", num(e.r_ros2), num(e.r_oracle)), "in range, R within 1 %",
             ok ? "within" : "outside"});
  }
  // Every rate constant x or / 10^3, at the biphasic peak's 0.3 nM, the tip 10x.
  {
    struct Rate {
      const char* name;
      double core::SignallingParams::*field;
    };
    const Rate rates[] = {{"kpA", &core::SignallingParams::kpA}, {"kmA", &core::SignallingParams::kmA},
                          {"kpI", &core::SignallingParams::kpI}, {"kr", &core::SignallingParams::kr},
                          {"kdegA", &core::SignallingParams::kdegA}, {"ka", &core::SignallingParams::ka},
                          {"a2", &core::SignallingParams::a2},   {"b2", &core::SignallingParams::b2},
                          {"g1", &core::SignallingParams::g1},   {"a6", &core::SignallingParams::a6},
                          {"b6", &core::SignallingParams::b6},   {"a1", &core::SignallingParams::a1},
                          {"b1", &core::SignallingParams::b1},   {"b0", &core::SignallingParams::b0}};
    int passed = 0, total = 0;
    std::string worst;
    double worst_err = 0;
    for (const Rate& rate : rates)
      for (double f : {1e-3, 1e3}) {
        core::SignallingParams q = base;
        q.*rate.field *= f;
        const Outcome e = integrate(q, 0.3, 3.0, 96);
        const double err = std::fabs(e.r_ros2 - e.r_oracle) / e.r_oracle;
        const bool ok = e.status == core::StiffStatus::kOk && e.in_range && err <= 0.01;
        passed += ok;
        ++total;
        if (!ok || !(err <= worst_err)) {  // the worst case (a failure, or a NaN, first)
          worst = fmt::format("{} x {}: R error {}", rate.name, num(f), num(err));
          worst_err = ok ? err : HUGE_VAL;
        }
      }
    r.check({"signalling with each of 14 rate constants x or / 10^3 (28 cases)", passed == total,
             fmt::format("{} of {} in range and within 1 %; largest: {}", passed, total, worst), "all", ""});
  }
  // Error against run time: 48 h at 0.3 nM, the tip at 0.33 nM, 24 to 1536 steps.
  std::vector<int> steps{24, 48, 96, 192, 384, 768, 1536};
  if (o.quick) steps.resize(4);
  std::vector<double> errs, secs;
  for (int n : steps) {
    const int reps = std::max(1, 20000 / n);
    const auto t0 = std::chrono::steady_clock::now();
    double y[core::kSignalSpecies];
    for (int rep = 0; rep < reps; ++rep) {
      core::signalling_steady_state(base, 0.3, inhibition(base, 0.3), y);
      core::signalling_step(base, y, 0.33, inhibition(base, 0.3), 2880.0, n);
    }
    secs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / reps);
    errs.push_back(integrate(base, 0.3, 0.33, n).max_rel);
  }
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < steps.size(); ++k)
    rows.push_back({std::to_string(steps[k]), num(2880.0 / steps[k]), num(errs[k]), fmt::format("{:.2f}", 1e6 * secs[k]),
                    k ? fmt::format("{:.2f}", std::log2(errs[k - 1] / errs[k])) : ""});
  r.text("Error against run time (48 h at 0.3 nM, the tip at 0.33 nM; one thread):");
  r.table({"steps per 48 h", "step (min)", "max relative error vs msbdf", "time per axon (us)", "order"}, rows,
          "signalling_work_precision.csv");
  const double order = std::log2(errs[errs.size() - 2] / errs.back());
  r.check({"signalling ROS2: observed order against the step (finest pair)", order > 1.7 && order < 2.5,
           fmt::format("{:.2f}", order), "2 (between 1.7 and 2.5)", ""});
}

}  // namespace

void validate_stiff(const Options& o, Report& r) {
  r.text("Each row runs one extreme case. A grid case passes when every sampled value is finite, non-negative "
         "and at most one step's deposit (a Q / h^3); a steering case when the heading stays a finite unit "
         "vector; a placement case when it succeeds or refuses with exit-3 text naming the packing fraction, in "
         "bounded time; a sampler case when every point is a finite unit vector.");
  const double deposit_bound = 0.01 * 100;  // a Q, divided by h^3 below
  struct GridCase {
    const char* name;
    GridScheme scheme;
    double d, k, h;
  };
  const GridCase grid_cases[] = {
      {"implicit, k dt = 1e6", GridScheme::kImplicit, 0.05, 1e6, 0.1},
      {"implicit, D dt / h^2 = 1e4", GridScheme::kImplicit, 100, 0.05, 0.1},
      {"implicit, k dt = 1e6 and D dt / h^2 = 1e4", GridScheme::kImplicit, 100, 1e6, 0.1},
      {"implicit, D dt / h^2 = 1e8 (k = 0)", GridScheme::kImplicit, 1e6, 0.0, 0.1},
      {"explicit, D dt / h^2 = 100 (sub-steps)", GridScheme::kExplicit, 1.0, 0.05, 0.1},
      {"explicit, k dt = 1e3 (sub-steps)", GridScheme::kExplicit, 0.05, 1e3, 0.2},
  };
  with_threads(o.threads, [&] {
    for (const GridCase& c : grid_cases) {
      const Scene s = one_source(FieldKind::kGrid, c.scheme, c.d, c.k, c.h);
      const auto cues = make_cues(s);
      auto f = make_reference_field(s, cues);
      PhaseTimes t;
      for (std::uint32_t step = 1; step <= (o.quick ? 3u : 10u); ++step) f->advance(step, t);
      const Scan sc = scan_field(*f, 1.9);
      const double bound = deposit_bound / (c.h * c.h * c.h);
      const bool ok = sc.finite && sc.min >= 0.0 && sc.max <= bound;
      r.check({std::string("grid ") + c.name, ok,
               fmt::format("finite={}, min={}, max={}{}", sc.finite, num(sc.min), num(sc.max),
                           f->note().empty() ? "" : "; " + f->note()),
               fmt::format("finite, >= 0, <= {}", num(bound)), ok ? "within" : "outside"});
    }
    {
      Scene s = one_source(FieldKind::kGrid, GridScheme::kExplicit, 100, 0.05, 0.1);
      s.cues.grid.allow_substeps = false;
      std::string what;
      try {
        make_reference_field(s, make_cues(s));
      } catch (const InputError& e) {
        what = e.what();
      }
      r.check({"explicit with sub-steps forbidden refuses (exit 2)", what.find("allow_substeps") != std::string::npos,
               what.empty() ? "accepted" : what.substr(0, 80) + "...", "InputError naming cues.grid.allow_substeps",
               ""});
    }
    {
      const Scene s = one_source(FieldKind::kParticles, GridScheme::kImplicit, 0.05, 1e6, 0.1);
      auto f = make_reference_field(s, make_cues(s));
      PhaseTimes t;
      for (std::uint32_t step = 1; step <= 5; ++step) f->advance(step, t);
      const Scan sc = scan_field(*f, 1.9);
      r.check({"particles, k dt = 1e6: every particle dies at once", sc.finite && f->particles() == 0 && sc.max == 0,
               fmt::format("{} particles, max C {}", f->particles(), num(sc.max)), "0 particles, C = 0, finite", ""});
    }
    {
      const Scene s = one_source(FieldKind::kAnalytic, GridScheme::kImplicit, 0.05, 0.0, 0.1);
      const auto cues = make_cues(s);
      const auto sp = sense_params(s);
      bool ok = true;
      for (double rr : {0.0, 1e-300, 1e-3, 1.0, 1e6, 1e300}) {
        const core::CueSample v = core::analytic_sample(cues[0].position + Vec3{rr, 0, 0}, cues[0], sp);
        ok = ok && std::isfinite(v.c) && v.c >= 0 && std::isfinite(core::norm(v.grad));
      }
      r.check({"analytic field at r = 0, 1e-300, ..., 1e300 (k = 0)", ok, ok ? "finite" : "non-finite", "finite, >= 0",
               ""});
    }
  });

  // Steering extremes.
  {
    bool ok = true;
    for (core::NoiseForm noise : {core::NoiseForm::kBinding, core::NoiseForm::kSnapshot}) {
      const core::SteerParams p = default_snr_params(noise);
      for (double gamma : {0.0, 1e-300, 1e-10, 0.5, 1.0, 1e10, 1e300, DBL_MAX, HUGE_VAL}) {
        ok = ok && std::isfinite(core::receptor_noise(gamma, noise));
        for (double mu : {1e-300, 1.0, 1e300})
          ok = ok && unit_and_finite(one_cue_decision({0, 0, 1}, gamma, mu, {1, 0, 0}, p, 1, 2, 3).heading);
      }
    }
    r.check({"SNR steering for gamma = 0 ... inf, mu = 1e-300 ... 1e300, both noise forms", ok,
             ok ? "finite unit headings" : "non-finite", "finite unit", ""});
    bool par = true;
    const core::SteerParams p = default_snr_params(core::NoiseForm::kBinding);
    for (Vec3 g : {Vec3{0, 0, 1}, Vec3{0, 0, -1}})
      for (std::uint32_t n = 0; n < 1000; ++n)
        par = par && unit_and_finite(one_cue_decision({0, 0, 1}, 0.5, 1.0, g, p, 1, n, 1).heading);
    r.check({"heading parallel and antiparallel to the gradient", par, par ? "finite unit headings (2000 decisions)" : "non-finite",
             "finite unit", ""});
    const core::CueParams cue{{0, 0, 0}, 1, 1, 1, 1, 1, 0, 1e300, 1, 1, 1, 1};
    const bool zero = !core::detected(core::exact_sample(1.0, {0, 0, 0}), cue) &&
                      !core::detected(core::exact_sample(0.0, {1, 0, 0}), cue);
    r.check({"zero gradient or zero concentration: cue not detected", zero, zero ? "ignored" : "detected", "ignored", ""});
    // Wandering and growth-rate modulation at the extremes of their parameters.
    bool wander_ok = true;
    for (double lp : {1e-300, 1e-6, 1.0, 1e6, 1e300})
      for (double l : {1e-300, 0.35, 1e300}) {
        core::WanderParams w{true, 1.0 / lp, 0.0, 0.0};
        wander_ok = wander_ok && unit_and_finite(core::wander({0, 0, 1}, l, false, w, 1, 2, 3));
      }
    r.check({"wandering for L_p = 1e-300 ... 1e300 and l = 1e-300 ... 1e300", wander_ok,
             wander_ok ? "finite unit headings" : "non-finite", "finite unit", ""});
    bool mod_ok = true;
    core::SteerParams pm = p;
    for (double m : {0.0, 0.5, 0.999999})
      for (double z : {-HUGE_VAL, -1e300, -1.0, 0.0, 1.0, 1e300}) {
        pm.modulation = m;
        const double l = core::modulated_step(0.35, z, pm);
        mod_ok = mod_ok && std::isfinite(l) && l >= 0.0 && l <= 0.35 * (1 + m);
      }
    r.check({"growth-rate modulation for m = 0 ... 0.999999 and evidence -inf ... 1e300", mod_ok,
             mod_ok ? "finite steps in [0, l0 (1 + m)]" : "out of range", "finite, within l0 (1 -+ m)", ""});
  }

  // Packing near the limit.
  {
    auto place = [&](double phi) {
      Scene s;
      s.neurons.count = o.quick ? 2000 : 10000;
      s.neurons.radius = 10;
      s.neurons.soma_radius = 10 * std::cbrt(phi / static_cast<double>(s.neurons.count));
      s.neurons.max_attempts = 2000;
      std::string outcome;
      const auto t0 = std::chrono::steady_clock::now();
      try {
        with_threads(o.threads, [&] { place_neurons(s); });
        outcome = "placed";
      } catch (const RunError& e) {
        outcome = e.what();
      }
      return std::make_pair(outcome, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    };
    const auto [a, ta] = place(0.25);
    r.check({"packing fraction 0.25 (below random sequential addition's jamming, ~0.38)", a == "placed",
             fmt::format("{} in {:.2f} s", a.substr(0, 60), ta), "placed", ""});
    const auto [b, tb] = place(0.45);
    const bool refused = b.find("packing fraction") != std::string::npos;
    r.check({"packing fraction 0.45 (above jamming) refuses with a clear error", refused && tb < 120,
             fmt::format("{} ({:.2f} s)", b.substr(0, 90), tb), "RunError naming the packing fraction, < 120 s", ""});
    const auto [c, tc] = place(0.8);
    r.check({"packing fraction 0.8 (above close packing) refuses at once", c.find("exceeds the densest packing") != std::string::npos && tc < 1,
             fmt::format("{} ({:.3f} s)", c.substr(0, 90), tc), "refused before sampling, < 1 s", ""});
  }

  // Samplers at d = 1000.
  for (core::Sampler m : {core::Sampler::kNormal, core::Sampler::kCoordinate}) {
    std::vector<double> x(1000);
    bool ok = true;
    const int n = o.quick ? 20 : 200;
    for (int i = 0; i < n; ++i) {
      core::Rng rng(5, core::Stream::kValidation, static_cast<std::uint64_t>(i), 200);
      sample_direction(m, rng, 1000, x.data());
      double s = 0;
      for (double v : x) ok = ok && std::isfinite(v), s += v * v;
      ok = ok && std::fabs(std::sqrt(s) - 1) < 1e-12;
    }
    r.check({fmt::format("{} sampler at d = 1000", name_of(m)), ok, ok ? fmt::format("{} finite unit vectors", n) : "bad",
             "finite, |x| = 1 within 1e-12", ""});
  }
  {
    std::string what;
    try {
      std::vector<double> x(20);
      core::Rng rng(5, core::Stream::kValidation, 0, 201);
      sample_direction(core::Sampler::kRejection, rng, 20, x.data());
    } catch (const InputError& e) {
      what = e.what();
    }
    r.check({"rejection sampler at d = 20 refuses (acceptance collapses)", what.find("acceptance rate") != std::string::npos,
             what.substr(0, 90), "InputError naming the acceptance rate", ""});
  }
  validate_signalling(o, r);
}

}  // namespace axg::validate
