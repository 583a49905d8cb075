// `validate guidance` C: the explant, every field against the analytic field.
#include "shared.hpp"

namespace axg::validate::guidance {

namespace {


ExplantStudy explant_study(const Options& o, AnalyticCache& analytic, double default_amount, double default_h) {
  ExplantStudy st;
  const int particle_seeds = o.quick ? 6 : 8, grid_seeds = o.quick ? 2 : 4;
  struct Family {
    FieldKind field;
    GridScheme scheme;
  };
  const Family families[] = {{FieldKind::kParticles, GridScheme::kImplicit},
                             {FieldKind::kGrid, GridScheme::kImplicit},
                             {FieldKind::kGrid, GridScheme::kExplicit}};
  for (const Family& fam : families) {
    const std::vector<Level> levels = ladder(fam.field, fam.scheme, default_amount, default_h, o.quick);
    std::vector<double> lh, lb, lc;
    for (const Level& lv : levels) {
      EvidenceError ev;
      if (fam.field == FieldKind::kGrid) {
        ev = evidence_error(lv.res);
        st.evidence.push_back({lv.res.method(), lv.res.label(), std::to_string(lv.level), num(ev.binding), num(ev.count),
                               num(ev.seconds)});
        lh.push_back(std::log(lv.res.spacing)), lb.push_back(std::log(ev.binding)), lc.push_back(std::log(ev.count));
      }
      for (core::NoiseForm form : kForms) {
        const int seeds = fam.field == FieldKind::kParticles ? particle_seeds : grid_seeds;
        ExplantRow row{noise_name(form), lv.res.method(), lv.res.label(), lv.level,
                       fam.field == FieldKind::kParticles ? lv.res.amount : lv.res.spacing,
                       explant_point(lv.res, form, seeds, analytic), NAN};
        if (fam.field == FieldKind::kGrid) row.evidence = form == core::NoiseForm::kCount ? ev.count : ev.binding;
        st.rows.push_back(row);
      }
    }
    if (fam.field == FieldKind::kGrid) {
      const std::string m = levels[0].res.method();
      st.evidence_fits[m + " binding"] = fit_line(lh, lb);
      st.evidence_fits[m + " count"] = fit_line(lh, lc);
    }
  }
  // The analytic field's own index at 1, 2, 4, 8, 16 seeds: its statistical error only.
  for (core::NoiseForm form : kForms) {
    double t1 = 0;
    for (int seeds : {1, 2, 4, 8, 16}) {
      if (o.quick && seeds > 4) break;
      std::vector<std::vector<double>> per;
      double secs = 0;
      for (int sd = 1; sd <= seeds; ++sd) {
        double t = 0;
        per.push_back(analytic.get(form, static_cast<std::uint64_t>(sd), &t));
        secs += t;
      }
      if (seeds == 1) t1 = secs;
      const MeanSe m = clustered(per);
      st.analytic_by_seeds.push_back({noise_name(form), std::to_string(seeds), num(m.mean, 4), num(m.se, 3),
                                      num(std::max(secs, t1 * seeds))});
    }
  }
  return st;
}


}  // namespace

void explant(const Options& o, Report& r, AnalyticCache& analytic, ExplantStudy& st) {
  r.heading("C. The explant: every field converges to the analytic field's guidance");
  const double default_amount = Scene{}.cues.particles.amount;
  const double default_h = kExplantGridSpacing;
  r.text(fmt::format(
      "The explant: 400 neurons in a ball of radius 1, somas of radius 0.005, one attractant at (4, 0, 0) with a Q = "
      "{} per step, D = 0.5, k = 0.05 (lambda = 3.2 LU), K_d = 0.5, no wandering, 30 steps of 0.2 LU, bounds 12 LU; "
      "particle and grid fields warmed up 100 steps (5 particle lifetimes, 33 diffusion times to the explant), so that "
      "every field starts at the steady state the analytic field is. Guidance index = mean cos(tip - soma, source - "
      "soma). Every resolution is paired by seed with the analytic field under the same noise form (the same somas, "
      "headings and decision streams): the gap is index - analytic index, its SE the larger of the pooled per-axon SE "
      "and the SE over seeds. Seeds 1..{} for particles, 1..{} for grids. Ladders about each field's default (level "
      "0): particles a = {} x 2^-level (the emission 2/a: the same source); grids h = {} x 2^-level, the implicit "
      "scheme's sub-steps 2^level at positive levels. Noise forms: count (molecule amount {:.4g} CU LU^3, the default "
      "reading of LU and CU), binding and snapshot (gain 250).\n\nCriteria, fixed in advance: (i) at level 0 every "
      "field's index is within max(10 %, 2 SE) of the analytic index under every form; (ii) particles: the gap at the "
      "finest level is within 3 SE of zero, smaller than at the coarsest by more than 3 combined SE, and its order in "
      "the amount (log-log slope over the levels whose gap exceeds 2 SE) lies in [0.5, 1.5] (the estimate's noise "
      "variance is proportional to a and weakens guidance in proportion to it); (iii) grids: the gap at every level is "
      "within max(10 %, 2 SE), and the grids' deterministic evidence error at the probes falls with h at an order in "
      "[0.8, 2.7] (the interpolation is O(h^2); the implicit scheme's splitting error is O(dt / m)); (iv) the grids' "
      "default spacing (level 0, the rule min(r, lambda / 6)) is the cheapest level whose evidence error is within 10 %.",
      kExplantStrength, o.quick ? 4 : 8, o.quick ? 2 : 4, default_amount, default_h, Scene{}.molecule_amount()));
  st = explant_study(o, analytic, default_amount, default_h);
  std::vector<std::vector<std::string>> rows;
  for (const ExplantRow& e : st.rows)
    rows.push_back({e.form, e.method, e.label, std::to_string(e.level), num(e.resolution), num(e.p.index.mean, 4),
                    num(e.p.index.se, 2), num(e.p.gap.mean, 3), num(e.p.gap.se, 2),
                    num(100.0 * e.p.gap.mean / (e.p.index.mean - e.p.gap.mean), 3), num(e.p.seconds, 3),
                    std::isnan(e.evidence) ? "" : num(e.evidence, 3)});
  r.table({"form", "method", "resolution", "level", "a or h", "index", "index SE", "gap", "gap SE", "gap %", "seconds per run",
           "evidence error"},
          rows, "guidance_explant.csv");
  r.table({"method", "resolution", "level", "evidence error binding and snapshot", "evidence error count", "seconds"},
          st.evidence, "guidance_evidence.csv");
  r.table({"form", "seeds", "analytic index", "SE", "seconds"}, st.analytic_by_seeds, "guidance_analytic_seeds.csv");
  // (i) level 0 within 10 % (or 2 SE)
  bool within = true;
  double worst = 0;
  std::string worst_what;
  for (const ExplantRow& e : st.rows) {
    if (e.level != 0) continue;
    const double ref = e.p.index.mean - e.p.gap.mean;
    const double allowed = std::max(0.1 * std::fabs(ref), 2.0 * e.p.gap.se);
    const double ratio = std::fabs(e.p.gap.mean) / allowed;
    if (ratio > worst) worst = ratio, worst_what = e.form + ", " + e.method + " " + e.label;
    if (ratio > 1) within = false;
  }
  r.check({"explant: at the default resolution every field's index is within max(10 %, 2 SE) of the analytic index "
           "(every noise form)",
           within, fmt::format("largest |gap| / allowance = {:.3f} ({})", worst, worst_what), "at most 1",
           fmt::format("{:.2f} of the allowance", worst)});
  // (ii) particles converge, with order
  std::vector<std::vector<std::string>> orders;
  for (core::NoiseForm form : kForms) {
    std::vector<const ExplantRow*> p;
    for (const ExplantRow& e : st.rows)
      if (e.method == "particles" && e.form == noise_name(form)) p.push_back(&e);
    const ExplantRow& coarse = *p.front();
    const ExplantRow& fine = *p.back();
    std::vector<double> x, y;
    for (const ExplantRow* e : p)
      if (std::fabs(e->p.gap.mean) > 2 * e->p.gap.se) x.push_back(std::log(e->resolution)), y.push_back(std::log(std::fabs(e->p.gap.mean)));
    const Fit fit = x.size() >= 2 ? fit_line(x, y) : Fit{NAN, NAN, NAN};
    orders.push_back({noise_name(form), "particles", "gap vs a", std::to_string(x.size()), num(fit.slope, 3),
                      num(fit.slope_se, 2), "1"});
    const double zf = std::fabs(fine.p.gap.mean) / fine.p.gap.se;
    const double zs = (std::fabs(coarse.p.gap.mean) - std::fabs(fine.p.gap.mean)) / std::hypot(coarse.p.gap.se, fine.p.gap.se);
    r.check({fmt::format("explant, {}: the particle field's gap shrinks ({} -> {})", noise_name(form), coarse.label, fine.label),
             zs > 3, fmt::format("{:.4f} -> {:.4f}", coarse.p.gap.mean, fine.p.gap.mean), "decrease above 3 combined SE",
             fmt::format("{:.1f} SE", zs)});
    if (!o.quick)
      r.check({fmt::format("explant, {}: at {} the particle field's gap is within 3 SE of zero", noise_name(form), fine.label),
               zf < 3, fmt::format("gap {:.4f} +- {:.4f} (z = {:.2f})", fine.p.gap.mean, fine.p.gap.se, zf), "|z| < 3",
               fmt::format("{:.2f} below the bound", 3 - zf)});
    if (x.size() >= 3)
      r.check({fmt::format("explant, {}: order of the particle field's gap in the amount", noise_name(form)),
               fit.slope > 0.5 && fit.slope < 1.5, fmt::format("{:.3f} +- {:.2f} over {} levels", fit.slope, fit.slope_se, x.size()),
               "slope in [0.5, 1.5] (theory 1)", fmt::format("{:+.3f} from 1", fit.slope - 1)});
    else
      r.skip(fmt::format("explant, {}: order of the particle field's gap in the amount", noise_name(form)),
             fmt::format("{} level(s) with a gap above 2 SE: no fit of three points", x.size()));
  }
  // (iii) grids
  bool grid_ok = true;
  double grid_worst = 0;
  for (const ExplantRow& e : st.rows) {
    if (e.method == "particles") continue;
    const double ref = e.p.index.mean - e.p.gap.mean;
    const double ratio = std::fabs(e.p.gap.mean) / std::max(0.1 * std::fabs(ref), 2.0 * e.p.gap.se);
    grid_worst = std::max(grid_worst, ratio);
    if (ratio > 1) grid_ok = false;
  }
  r.check({"explant: every grid resolution of the ladders guides within max(10 %, 2 SE) of the analytic field", grid_ok,
           fmt::format("largest |gap| / allowance = {:.3f}", grid_worst), "at most 1", fmt::format("{:.2f} of it", grid_worst)});
  for (const auto& [name, fit] : st.evidence_fits) {
    orders.push_back({name.substr(name.rfind(' ') + 1), name.substr(0, name.rfind(' ')), "evidence error vs h", "all",
                      num(fit.slope, 3), num(fit.slope_se, 2), "2 (explicit), 1-2 (implicit: h^2 and dt / m)"});
    r.check({fmt::format("explant, {}: order of the evidence error in h", name), fit.slope > 0.8 && fit.slope < 2.7,
             fmt::format("{:.3f} +- {:.2f}", fit.slope, fit.slope_se), "slope in [0.8, 2.7]",
             fmt::format("{:+.3f} from 2", fit.slope - 2)});
  }
  // The grids' default spacing is the rule's min(r, lambda / 6): the cheapest level of the
  // ladder whose evidence error is within 10 % (guidance alone saturates: even h = 4 lambda / 6
  // guides within 10 % here, with half the evidence wrong).
  {
    bool ok = true;
    std::string what;
    for (const ExplantRow& e : st.rows) {
      if (e.method == "particles" || std::isnan(e.evidence) || (e.level != 0 && e.level != -1)) continue;
      const bool within = e.evidence <= 0.1;
      if ((e.level == 0) != within) ok = false, what += fmt::format("{} {} level {}: {:.3f}; ", e.method, e.form, e.level, e.evidence);
    }
    r.check({"explant: the grids' default spacing is the cheapest level with an evidence error within 10 % (every form)",
             ok, ok ? std::string("level 0 within, level -1 not, for both schemes") : what, "level 0 <= 0.1 < level -1",
             ok ? "yes" : "no"});
  }
  r.table({"form", "method", "error", "points fitted", "order", "SE", "theory"}, orders, "guidance_explant_orders.csv");
  r.plot("guidance_explant.py", {"guidance_explant.csv"}, "guidance_explant.png",
         "Explant: guidance index against resolution for every field and noise form (95 % CIs), the analytic index "
         "dashed; the gap to the analytic index against the amount (particles) and the spacing (grids), log-log.");
}


}  // namespace axg::validate::guidance
