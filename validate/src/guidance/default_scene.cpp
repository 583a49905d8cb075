// `validate guidance` E: the default scene at two resolutions.
#include "shared.hpp"

namespace axg::validate::guidance {

void default_scene(const Options& o, Report& r) {
  const double factor = o.quick ? 4 : 16;
  const int seeds = o.quick ? 2 : 4;
  r.heading(fmt::format("E. The default scene at {} times the particles", factor));
  r.text(fmt::format(
      "The built-in default scene (1000 neurons, two attractants and two repellents, count noise) at the default "
      "amount a = 0.001 and at a / {} with the emission x {} (the same sources), seeds 1..{}. Metrics: the fraction "
      "connected, the mean length of connected axons, the fraction exited, and the guidance index (per neuron the mean "
      "over the cues of sign_k cos(tip - soma, p_k - soma)). Paired by seed (same somas, headings and decision "
      "streams); SEs pooled over neurons (the larger of that and the SE over seeds), Welch's for the lengths. "
      "Criteria, fixed in advance: every difference within {:.2f} SE (alpha = {} over four metrics).",
      factor, factor, seeds, z_bound(4), kAlpha));
  Resolution base, fine;
  base.field = fine.field = FieldKind::kParticles;
  base.amount = 0.001;
  fine.amount = 0.001 / factor;
  std::vector<std::vector<double>> dg, dc, de, gb, gf, cb, cf, eb, ef;
  std::vector<double> lb, lf;
  double tb = 0, tf = 0;
  for (int sd = 1; sd <= seeds; ++sd) {
    const Timed rb = timed_run(default_scene_at(static_cast<std::uint64_t>(sd), base));
    const Timed rf = timed_run(default_scene_at(static_cast<std::uint64_t>(sd), fine));
    const Network nb = network_of(rb), nf = network_of(rf);
    tb += nb.seconds / seeds, tf += nf.seconds / seeds;
    std::vector<double> g(nb.guidance.size()), c(g.size()), e(g.size()), xb(g.size()), xf(g.size());
    for (std::size_t i = 0; i < g.size(); ++i) {
      g[i] = nf.guidance[i] - nb.guidance[i];
      c[i] = nf.connected[i] - nb.connected[i];
      xb[i] = rb.result.neurons.status[i] == core::AxonStatus::kExited ? 1.0 : 0.0;
      xf[i] = rf.result.neurons.status[i] == core::AxonStatus::kExited ? 1.0 : 0.0;
      e[i] = xf[i] - xb[i];
    }
    dg.push_back(g), dc.push_back(c), de.push_back(e), eb.push_back(xb), ef.push_back(xf);
    gb.push_back(nb.guidance), gf.push_back(nf.guidance), cb.push_back(nb.connected), cf.push_back(nf.connected);
    lb.insert(lb.end(), nb.length.begin(), nb.length.end());
    lf.insert(lf.end(), nf.length.begin(), nf.length.end());
  }
  const MeanSe mlb = mean_se(lb), mlf = mean_se(lf);
  struct Metric {
    const char* name;
    double base, fine;
    MeanSe diff;
  };
  std::vector<Metric> metrics{
      {"guidance index", clustered(gb).mean, clustered(gf).mean, clustered(dg)},
      {"fraction connected", clustered(cb).mean, clustered(cf).mean, clustered(dc)},
      {"fraction exited", clustered(eb).mean, clustered(ef).mean, clustered(de)},
      {"mean length of connected axons", mlb.mean, mlf.mean, {mlf.mean - mlb.mean, std::hypot(mlb.se, mlf.se)}}};
  const double zc = z_bound(4);
  std::vector<std::vector<std::string>> rows;
  bool ok = true;
  double worst = 0;
  for (const Metric& m : metrics) {
    const double z = m.diff.mean / m.diff.se;
    worst = std::max(worst, std::fabs(z));
    if (!(std::fabs(z) < zc)) ok = false;
    rows.push_back({m.name, num(m.base, 4), num(m.fine, 4),
                    num(m.diff.mean, 3), num(m.diff.se, 2), num(z, 3)});
  }
  rows.push_back({"seconds per run", num(tb, 3), num(tf, 3), "", "", ""});
  r.table({"metric", "a = 0.001", fmt::format("a = 0.001 / {}", factor), "difference", "SE", "z"}, rows,
          "guidance_default_scene.csv");
  r.check({fmt::format("default scene: connections and guidance at the default amount and at {} x the particles agree", factor),
           ok, fmt::format("largest |z| = {:.3f}", worst), fmt::format("|z| < {:.2f} for all four metrics", zc),
           fmt::format("{:.2f} below the bound", zc - worst)});
}


}  // namespace axg::validate::guidance
