// `validate continuum`: guidance that stops moving when the numerics are refined (SPEC §3.5;
// docs/methods.md §2.6, §4.6). Every numerical parameter is refined over at least four levels
// on scenes that differ, and the answer (the explant's guidance index, the assay's bias, the
// default scene's connected fraction) must converge, with the order measured:
//  A. dt and the step length together (the step is speed x dt), on the `validate guidance`
//     explant with sensing radius 0.25, 0.5 and 1, the same with a source 10x weaker, every
//     noise form, the particle field, scenes/assay-explant.json in physical units and the
//     default scene; the report's per-step rule beside them as the control that does not
//     converge;
//  B. the particle amount;
//  C. the estimate's mesh spacing (at most r, the sensing ball's radius);
//  D. the estimate's time constant, refined with the amount so that the estimate's noise
//     (variance ~ a / tau) stays the same and only its lag falls;
//  E. the grid's spacing and its implicit sub-steps.
// Each ladder's default level must lie within max(10 %, 2 SE) of its finest level (the 2 SE
// margin only where the SE is at most 0.01), every level paired by seed with the finest (the
// same somas, headings and decision draws), and the successive differences must shrink. The
// error against run time of every ladder is plotted (the work-precision study).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

#include <fmt/format.h>

#include "axonguide/engine/run.hpp"
#include "axonguide/model/estimate.hpp"
#include "axonguide/model/stencil.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/study/assay.hpp"
#include "axonguide/study/sweep.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

using core::Vec3;
using sweep::MeanSe;
using sweep::mean_se;

const Vec3 kSource{4, 0, 0};

// The explant of `validate guidance` (explant_base) with sensing radius r and source strength
// a Q per time unit, at dt = T = 1 (30 decisions); the fields warmed up 100 time units.
Scene explant(std::uint64_t seed, double r, double strength, core::NoiseForm noise, FieldKind field) {
  Scene s = explant_base(seed, noise);
  s.dt = 1.0;
  s.guidance.sensing_radius = r;
  s.guidance.integration_time = 1.0;
  s.cues.sources[0].emission = strength * s.dt / s.cues.particles.amount;  // per step: a Q dt / a
  s.cues.field = field;
  s.cues.warmup_steps = field == FieldKind::kAnalytic ? 0 : 100;
  return s;
}

// dt and the step length divided by f: the same growth and the same physical source.
void refine_dt(Scene& s, double f) {
  s.dt /= f;
  s.steps = static_cast<std::uint32_t>(std::lround(s.steps * f));
  s.cues.warmup_steps = static_cast<std::uint32_t>(std::lround(s.cues.warmup_steps * f));
  s.axons.step_length /= f;  // growth_speed x dt when a speed is given (set when the scene was read)
  for (Source& src : s.cues.sources) src.emission /= f;
  s.cues.random_sources.emission /= f;
}

// The particle amount divided by f (f times the particles), the source unchanged.
void refine_amount(Scene& s, double f) {
  s.cues.particles.amount /= f;
  for (Source& src : s.cues.sources) src.emission *= f;
  s.cues.random_sources.emission *= f;
}

enum class Measure { kIndex, kBias, kConnected };

double measure(const Scene& s, const RunResult& res, Measure m) {
  if (m == Measure::kConnected)
    return static_cast<double>(res.stats.back().connected) / static_cast<double>(res.soma.size());
  if (m == Measure::kBias) return assay::measure(s, res.soma, res.neurons, res.cues).bias;
  double sum = 0.0;
  for (std::size_t i = 0; i < res.soma.size(); ++i) {
    const Vec3 a = res.neurons.tip[i] - res.soma[i], b = kSource - res.soma[i];
    sum += core::dot(a, b) / (core::norm(a) * core::norm(b));
  }
  return sum / static_cast<double>(res.soma.size());
}

// A ladder: level l's scene for a seed; level 0 is the default, the last the finest.
struct Ladder {
  std::string scene, parameter;
  Measure measure;
  std::vector<std::string> values;  // the parameter's value per level, for the report
  std::function<Scene(std::uint64_t seed, int level)> make;
  int seeds;
  int default_level = 0;
  bool control = false;  // the per-step rule: reported, not required to converge
};

// dt and the step refined by 2 per level from a base scene (its default dt at level 0).
Ladder dt_ladder(std::string scene, Measure m, std::function<Scene(std::uint64_t seed)> base, int seeds) {
  const double dt = base(1).dt;
  std::vector<std::string> values;
  for (int l = 0; l < 4; ++l) values.push_back(fmt::format("dt = {:.4g}", dt / std::pow(2.0, l)));
  return {std::move(scene), "dt, step", m, values,
          [base](std::uint64_t seed, int l) {
            Scene s = base(seed);
            refine_dt(s, std::pow(2.0, l));
            return s;
          },
          seeds};
}

struct Point {
  MeanSe value, diff;  // diff: paired with the finest level, per seed
  double seconds = 0;  // per run
};

std::vector<Point> run_ladder(const Ladder& l) {
  const int levels = static_cast<int>(l.values.size());
  std::vector<std::vector<double>> v(static_cast<std::size_t>(levels));
  std::vector<double> secs(static_cast<std::size_t>(levels), 0.0);
  for (int lv = 0; lv < levels; ++lv)
    for (int sd = 1; sd <= l.seeds; ++sd) {
      const Scene s = l.make(static_cast<std::uint64_t>(sd), lv);
      RunOptions ro;
      const auto t0 = std::chrono::steady_clock::now();
      const RunResult res = run_scene(s, ro);
      secs[static_cast<std::size_t>(lv)] +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      v[static_cast<std::size_t>(lv)].push_back(measure(res.scene, res, l.measure));
    }
  std::vector<Point> out;
  const std::vector<double>& finest = v.back();
  for (int lv = 0; lv < levels; ++lv) {
    std::vector<double> d;
    for (std::size_t k = 0; k < finest.size(); ++k) d.push_back(v[static_cast<std::size_t>(lv)][k] - finest[k]);
    out.push_back({mean_se(v[static_cast<std::size_t>(lv)]), mean_se(d), secs[static_cast<std::size_t>(lv)] / l.seeds});
  }
  return out;
}

// The order of the successive differences d_l = m_(l+1) - m_l: the slope of -log2 |d_l|
// against l by least squares (over every difference; 0 when fewer than two are nonzero).
double order_of(const std::vector<Point>& p) {
  std::vector<double> x, y;
  for (std::size_t l = 0; l + 1 < p.size(); ++l) {
    const double d = std::fabs(p[l + 1].value.mean - p[l].value.mean);
    if (d > 0.0) x.push_back(static_cast<double>(l)), y.push_back(-std::log2(d));
  }
  if (x.size() < 2) return 0.0;
  return fit_line(x, y).slope;
}

}  // namespace

void validate_continuum(const Options& o, Report& r) {
  const int analytic_seeds = o.quick ? 8 : 16, particle_seeds = o.quick ? 3 : 6;
  const double a0 = Scene{}.cues.particles.amount;
  std::vector<Ladder> ladders;
  // A. dt and the step together.
  using core::NoiseForm;
  for (double radius : {0.25, 0.5, 1.0})
    ladders.push_back(dt_ladder(fmt::format("explant r = {}", radius), Measure::kIndex,
                                [radius](std::uint64_t seed) {
                                  return explant(seed, radius, 2.0, NoiseForm::kCount, FieldKind::kAnalytic);
                                },
                                analytic_seeds));
  ladders.push_back(dt_ladder("explant r = 0.5, source / 10", Measure::kIndex,
                              [](std::uint64_t seed) {
                                return explant(seed, 0.5, 0.2, NoiseForm::kCount, FieldKind::kAnalytic);
                              },
                              analytic_seeds));
  for (NoiseForm f : {NoiseForm::kBinding, NoiseForm::kSnapshot})
    ladders.push_back(dt_ladder(fmt::format("explant r = 0.5, {}", name_of(f)), Measure::kIndex,
                                [f](std::uint64_t seed) { return explant(seed, 0.5, 2.0, f, FieldKind::kAnalytic); },
                                analytic_seeds));
  Ladder control = dt_ladder("explant r = 0.5, per-step rule (control)", Measure::kIndex,
                             [](std::uint64_t seed) {
                               Scene s = explant(seed, 0.5, 2.0, NoiseForm::kCount, FieldKind::kAnalytic);
                               s.guidance.decision = DecisionRule::kPerStep;
                               return s;
                             },
                             analytic_seeds);
  control.control = true;
  ladders.push_back(control);
  ladders.push_back(dt_ladder("explant r = 0.5, particles", Measure::kIndex,
                              [](std::uint64_t seed) {
                                return explant(seed, 0.5, 2.0, NoiseForm::kCount, FieldKind::kParticles);
                              },
                              particle_seeds));
  const Scene assay_base = load_scene_file((data_dir() / "scenes" / "assay-explant.json").string()).scene;
  ladders.push_back(dt_ladder("assay-explant (um, h)", Measure::kBias,
                              [assay_base](std::uint64_t seed) {
                                Scene s = assay_base;
                                s.seed = seed;
                                s.neurons.populations[0].count = 4000;  // the bias's SE per explant is ~0.03
                                s.neurons.count = 4000;
                                return s;
                              },
                              o.quick ? 8 : 16));
  const Scene default_base = Scene::builtin_default();
  ladders.push_back(dt_ladder("default scene", Measure::kConnected,
                              [default_base](std::uint64_t seed) {
                                Scene s = default_base;
                                s.seed = seed;
                                return s;
                              },
                              o.quick ? 4 : 8));
  // B. The particle amount.
  for (double radius : {0.5, 1.0}) {
    std::vector<std::string> vals;
    for (int l = 0; l < 4; ++l) vals.push_back(fmt::format("a = {:.4g}", a0 / std::pow(2.0, l)));
    ladders.push_back({fmt::format("explant r = {}, particles", radius), "particle amount", Measure::kIndex, vals,
                       [radius](std::uint64_t seed, int l) {
                         Scene s = explant(seed, radius, 2.0, core::NoiseForm::kCount, FieldKind::kParticles);
                         refine_amount(s, std::pow(2.0, l));
                         return s;
                       },
                       particle_seeds});
  }
  // C. The estimate's mesh from r down to r / 2 (factor 2^(1/4) per level), at 8 times the
  // default's particles. Below about r / 2 the ball rule's 42 points, each reading the cells
  // about it, stop covering the ball, and at a fixed amount the estimate's noise grows as the
  // mesh is refined further (docs/methods.md §2.6): a finer mesh there needs more particles.
  for (double radius : {0.5, 1.0}) {
    std::vector<std::string> vals;
    for (int l = 0; l < 5; ++l) vals.push_back(fmt::format("h = {:.4g}", radius / std::pow(2.0, 0.25 * l)));
    ladders.push_back({fmt::format("explant r = {}, particles", radius), "estimate mesh", Measure::kIndex, vals,
                       [radius](std::uint64_t seed, int l) {
                         Scene s = explant(seed, radius, 2.0, core::NoiseForm::kCount, FieldKind::kParticles);
                         s.cues.particles.estimate.spacing = radius / std::pow(2.0, 0.25 * l);
                         refine_amount(s, 8.0);
                         return s;
                       },
                       particle_seeds});
  }
  // D. The estimate's time constant, tau = 10 T / 2^l with a / 2^l.
  {
    std::vector<std::string> vals;
    for (int l = 0; l < 4; ++l)
      vals.push_back(fmt::format("tau = {:.4g} T, a = {:.4g}", 10.0 / std::pow(2.0, l), a0 / std::pow(2.0, l)));
    ladders.push_back({"explant r = 0.5, particles", "estimate time", Measure::kIndex, vals,
                       [](std::uint64_t seed, int l) {
                         Scene s = explant(seed, 0.5, 2.0, core::NoiseForm::kCount, FieldKind::kParticles);
                         s.cues.particles.estimate.time = 10.0 / std::pow(2.0, l);
                         refine_amount(s, std::pow(2.0, l));
                         return s;
                       },
                       particle_seeds});
  }
  // E. The grid: spacing (the rule min(r, lambda / 6) = 0.5 at level 1) and sub-steps.
  {
    std::vector<std::string> vals;
    const int top = o.quick ? 3 : 4;
    for (int l = 0; l < top; ++l) vals.push_back(fmt::format("h = {:.4g}", 1.0 / std::pow(2.0, l)));
    Ladder g{"explant r = 0.5, implicit grid", "grid spacing", Measure::kIndex, vals,
             [](std::uint64_t seed, int l) {
               Scene s = explant(seed, 0.5, 2.0, core::NoiseForm::kCount, FieldKind::kGrid);
               s.cues.grid.spacing = 1.0 / std::pow(2.0, l);
               return s;
             },
             2};
    g.default_level = 1;
    ladders.push_back(g);
    std::vector<std::string> subs;
    for (int l = 0; l < 4; ++l) subs.push_back(fmt::format("{} sub-steps", 1 << l));
    ladders.push_back({"explant r = 0.5, implicit grid", "field sub-steps", Measure::kIndex, subs,
                       [](std::uint64_t seed, int l) {
                         Scene s = explant(seed, 0.5, 2.0, core::NoiseForm::kCount, FieldKind::kGrid);
                         s.cues.grid.spacing = 0.5;
                         s.cues.grid.substeps = 1u << l;
                         return s;
                       },
                       2});
  }

  r.text(
      "Every numerical parameter refined over four or more levels, each level paired by seed with the finest (the "
      "same somas, headings and decision draws: refinements share their noise, so their difference is the "
      "numerical error). The explant is `validate guidance`'s (400 neurons in a ball of radius 1, an attractant 4 LU "
      "away, 6 LU of growth, T = 1); its index is the mean cosine between an axon's net displacement and the "
      "direction to the source. The assay's bias is `axonguide assay`'s; the default scene's answer is its "
      "connected fraction. dt ladders divide dt, the step and the emission per step by 2 per level (the same growth "
      "and the same physical source). The estimate's time constant is refined with the amount (a / tau fixed: the "
      "same estimate noise, less lag). Criteria, fixed in advance: (i) the default level within max(10 %, 2 SE) of "
      "the finest (2 SE only where the SE is at most 0.01); (ii) the last successive difference no larger than the "
      "first, within 2 SE of zero, or below 1 % of the answer (converged to the study's resolution). The per-step rule is the control: it is reported, and it does not converge.");
  std::vector<std::vector<std::string>> rows, summary;
  for (const Ladder& l : ladders) {
    const std::vector<Point> p = run_ladder(l);
    for (std::size_t k = 0; k < p.size(); ++k)
      rows.push_back({l.scene, l.parameter, std::to_string(k), l.values[k], num(p[k].value.mean),
                      num(p[k].value.se, 2), num(p[k].diff.mean, 3), num(p[k].diff.se, 2), num(p[k].seconds, 3)});
    const Point& d = p[static_cast<std::size_t>(l.default_level)];
    const double finest = p.back().value.mean;
    const double se = d.diff.se;
    const double allowance = std::max(0.1 * std::fabs(finest), se <= 0.01 ? 2.0 * se : 0.0);
    const double first = std::fabs(p[1].value.mean - p[0].value.mean);
    const double last_diff = p[p.size() - 1].value.mean - p[p.size() - 2].value.mean;
    const double last_se = p[p.size() - 2].diff.se;
    const double order = order_of(p);
    const double rel = finest != 0.0 ? d.diff.mean / finest : 0.0;
    summary.push_back({l.scene, l.parameter, num(finest), num(d.diff.mean, 3), num(100.0 * rel, 3), num(se, 2),
                       num(order, 3), l.control ? "control" : ""});
    if (l.control) continue;
    r.check({fmt::format("{}, {}: the default within max(10 %, 2 SE) of the finest level", l.scene, l.parameter),
             std::fabs(d.diff.mean) <= allowance,
             fmt::format("{:+.4f} ({:+.1f} %, SE {:.4f})", d.diff.mean, 100.0 * rel, se),
             fmt::format("|gap| <= {:.4f}", allowance), fmt::format("{:.2f} of the allowance", std::fabs(d.diff.mean) / allowance)});
    r.check({fmt::format("{}, {}: the successive differences shrink", l.scene, l.parameter),
             std::fabs(last_diff) <= first || std::fabs(last_diff) <= 2.0 * last_se ||
                 std::fabs(last_diff) <= 0.01 * std::fabs(finest),
             fmt::format("first {:.4f}, last {:.4f} (SE {:.4f}), order {:.2f}", first, std::fabs(last_diff), last_se,
                         order),
             "last <= first, within 2 SE of 0, or below 1 % of the answer", fmt::format("last / first = {:.2f}", first > 0 ? std::fabs(last_diff) / first : 0.0)});
  }
  r.table({"scene", "parameter", "finest value", "default - finest", "gap %", "gap SE", "order", "note"}, summary,
          "continuum_summary.csv");
  r.csv("continuum.csv", {"scene", "parameter", "level", "value", "answer", "SE", "minus finest", "minus finest SE", "seconds per run"},
        rows);
  r.plot("continuum.py", {"continuum.csv"}, "continuum.png",
         "Work against precision: |answer - finest level| against seconds per run for every ladder (the finest "
         "level, at zero error, is left out); the per-step rule's control dashed.");
}

}  // namespace axg::validate
