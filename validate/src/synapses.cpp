// `validate synapses`: apposition detection (network/appositions.hpp; SPEC §3.9; docs/methods.md
// §2.13) against exact results.
//  A. Contacts of isotropic straight segments placed uniformly, against Steiner's formula:
//     E[contacts] = N_a N_d E[vol]/V, E[vol] = (π/2) d l_a l_d + π d² (l_a + l_d) + (4/3) π d³,
//     for three distances and two segment lengths. The axon segments' midpoints are uniform
//     in an inner cube and the dendrite segments' in the cube grown by a margin that holds
//     every contact body, so the count is exact without edge terms.
//  B. Appositions of long straight neurites cut into steps l, l/2, l/4, l/8: the contact
//     count grows as the step shrinks; the apposition count does not, and it equals the pairs
//     of neurites that come within d, whose expectation tends to the crossing term
//     (π/2) d L_a L_d / V for neurites much longer than d.
//  C. Exactness: on grown cultures, the spatial hash finds exactly the contacts of the
//     brute-force search, and the same appositions.
//  D. Convergence on grown arbours: appositions and connections per neuron as the sample
//     length and dt are refined.
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "axonguide/core/random.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/network/appositions.hpp"
#include "axonguide/scene/scene.hpp"
#include "axonguide/study/sweep.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

using core::Vec3;
using network::Polyline;

Vec3 isotropic(core::Rng& rng) {
  const double z = rng.symmetric();
  const double phi = 2.0 * M_PI * rng.uniform_co();
  const double r = std::sqrt(1.0 - z * z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Vec3 uniform_in_cube(core::Rng& rng, double side) {
  const double x = side * rng.uniform_co(), y = side * rng.uniform_co();
  return {x, y, side * rng.uniform_co()};
}

// Neuron 0: `na` axon neurites of length la, each cut into `cuts` segments, midpoints
// uniform in the inner cube [m, m + side]^3; neuron 1: `nd` dendrite neurites of length ld
// the same way, midpoints uniform in [0, side + 2m]^3. Somas far outside, radius 0.
network::Segments straight_neurites(std::uint64_t seed, std::uint32_t test, int na, double la, int nd, double ld,
                                    int cuts, double side, double margin) {
  std::vector<std::vector<Polyline>> neurons(2);
  auto neurite = [&](std::uint8_t type, std::uint64_t id, double length, double lo, double width) {
    core::Rng rng(seed, core::Stream::kValidation, id, test);
    const Vec3 mid = Vec3{lo, lo, lo} + uniform_in_cube(rng, width);
    const Vec3 u = isotropic(rng);
    Polyline l;
    l.type = type;
    const Vec3 a = mid - (0.5 * length) * u;
    // The same neurite whatever the cut: its k-th point at k/cuts of its length.
    for (int k = 0; k <= cuts; ++k) l.points.push_back(a + (length * k / cuts) * u);
    return l;
  };
  for (int i = 0; i < na; ++i) neurons[0].push_back(neurite(morphology::kAxonType, i, la, margin, side));
  for (int i = 0; i < nd; ++i)
    neurons[1].push_back(neurite(morphology::kDendriteType, 1000000 + i, ld, 0.0, side + 2.0 * margin));
  const double far = 4.0 * (side + 2.0 * margin);
  return network::segments_from_polylines(neurons, {{-far, 0, 0}, {far, 0, 0}}, 0.0);
}

double steiner(double d, double la, double ld) {
  return 0.5 * M_PI * d * la * ld + M_PI * d * d * (la + ld) + 4.0 / 3.0 * M_PI * d * d * d;
}

Scene culture_base() {
  return load_scene_file((data_dir() / "scenes" / "culture.json").string()).scene;
}

}  // namespace

void validate_synapses(const Options& o, Report& r) {
  r.text(
      "Apposition detection (`network/appositions.hpp`; SPEC §3.9; docs/methods.md §2.13): contacts against Steiner's "
      "formula, appositions of straight neurites against the crossing term as the step shrinks, the spatial hash "
      "against the brute-force search on grown cultures, and convergence on grown arbours.");
  SynapseParams all;
  all.distance = 1.0;

  // A. Contacts against Steiner's formula.
  r.heading("A. Contacts of isotropic uniform segments against Steiner's formula");
  {
    const int reps = o.quick ? 6 : 24, n = o.quick ? 1500 : 3000;
    const double side = 20.0;
    std::vector<std::vector<std::string>> t;
    double worst = 0;
    std::uint32_t test = 0;
    for (const double l : {1.0, 3.0})
      for (const double d : {0.1, 0.3, 1.0}) {
        const double margin = l + d;  // half of each segment plus d
        const double volume = std::pow(side + 2.0 * margin, 3);
        const double expected = static_cast<double>(n) * n * steiner(d, l, l) / volume;
        std::vector<double> counts;
        ++test;
        for (int rep = 0; rep < reps; ++rep) {
          const network::Segments g = straight_neurites(1000 + rep, test, n, l, n, l, 1, side, margin);
          counts.push_back(static_cast<double>(network::find_contacts(g, d, false).size()));
        }
        const sweep::MeanSe m = sweep::mean_se(counts);
        const double z = (m.mean - expected) / m.se;
        worst = std::max(worst, std::fabs(z));
        t.push_back({fmt::format("{}", l), fmt::format("{}", d), fmt::format("{:.2f} ± {:.2f}", m.mean, m.se),
                     fmt::format("{:.2f}", expected), fmt::format("{:+.2f}", z)});
      }
    r.table({"segment length", "d", "contacts per replicate", "Steiner expectation", "z"}, t, "synapses_contacts.csv");
    r.text(fmt::format(
        "{} axon and {} dendrite segments of one length, isotropic, midpoints uniform (axons in a cube of side {}, "
        "dendrites in that cube grown by the segment length plus d, so that every contact body lies inside it); {} "
        "replicates per row, mean ± SE. Expectation N_a N_d ((π/2) d l² + 2π d² l + (4/3) π d³)/V.",
        n, n, side, reps));
    r.check({"the contact count is Steiner's expectation at 3 distances and 2 lengths", worst <= 3.5,
             fmt::format("largest |z| = {:.2f} over 6 rows", worst), "|z| ≤ 3.5 (6 rows)",
             fmt::format("{:.2f}", 3.5 - worst)});
  }

  // B. Appositions of straight neurites as the step shrinks.
  r.heading("B. Appositions of long straight neurites as the step shrinks");
  {
    // Steps from 8d down to d: at a step near d, counting segment pairs counts a crossing
    // several times over.
    const int reps = o.quick ? 4 : 16, n = o.quick ? 500 : 1000;
    const double side = 20.0, length = 51.2, d = 0.1;
    const double margin = length + d;
    const double volume = std::pow(side + 2.0 * margin, 3);
    const double crossing = 0.5 * M_PI * d * (n * length) * (n * length) / volume;
    const double exact = static_cast<double>(n) * n * steiner(d, length, length) / volume;
    std::vector<std::vector<std::string>> t;
    double worst_exact = 0, z_crossing = 0;
    std::vector<double> coarsest;  // each replicate's count at the coarsest step
    for (const int cuts : {64, 128, 256, 512}) {
      std::vector<double> apps, contacts;
      std::uint64_t differing = 0;
      for (int rep = 0; rep < reps; ++rep) {
        const network::Segments g = straight_neurites(2000 + rep, 100, n, length, n, length, cuts, side, margin);
        const auto c = network::find_contacts(g, d, false);
        const network::Appositions a = network::group_appositions(g, c, all);
        apps.push_back(static_cast<double>(a.size()));
        contacts.push_back(static_cast<double>(c.size()));
        if (cuts == 64) coarsest.push_back(static_cast<double>(a.size()));
        differing += a.size() != static_cast<std::size_t>(coarsest[rep]);
      }
      const sweep::MeanSe ma = sweep::mean_se(apps), mc = sweep::mean_se(contacts);
      const double z = (ma.mean - exact) / ma.se;
      worst_exact = std::max(worst_exact, std::fabs(z));
      z_crossing = (ma.mean - crossing) / ma.se;
      t.push_back({fmt::format("{}", length / cuts), fmt::format("{:.2f} ± {:.2f}", mc.mean, mc.se),
                   fmt::format("{:.2f} ± {:.2f}", ma.mean, ma.se), std::to_string(differing),
                   fmt::format("{:+.2f}", z), fmt::format("{:+.2f}", z_crossing)});
      if (differing != 0)
        r.check({fmt::format("a straight pair is one apposition at step {}", length / cuts), false,
                 fmt::format("{} replicates differ from step {}", differing, length / 64), "0", "-"});
    }
    r.table({"step", "contacts", "appositions", "replicates whose count differs from step 0.8", "z (pairs within d)",
             "z (crossing term)"},
            t, "synapses_appositions.csv");
    r.text(fmt::format(
        "{} axon and {} dendrite neurites of length {} (straight, isotropic; midpoints uniform as in §A, inner cube of "
        "side {}), d = {}, {} replicates, each neurite cut into segments of the step. Contacts (segment pairs) grow as "
        "the step shrinks; appositions (runs of contacts) do not: the contacts of a straight pair fill a convex region "
        "of its parameter square, whose cells are neighbours, so each pair within d is one apposition at every step. "
        "Their exact expectation (Steiner's formula for the neurites) is {:.2f}; the crossing term (π/2) d L_a L_d / V "
        "is {:.2f} (the end terms are 4d/l = {:.1f} % of it).",
        n, n, length, side, d, reps, exact, crossing, 400.0 * d / length));
    r.check({"appositions equal the exact expectation of pairs within d at every step", worst_exact <= 3.0,
             fmt::format("largest |z| = {:.2f}", worst_exact), "|z| ≤ 3", fmt::format("{:.2f}", 3.0 - worst_exact)});
    r.check({"the finest step's appositions agree with the crossing term (π/2) d L_a L_d / V", std::fabs(z_crossing) <= 3.0,
             fmt::format("z = {:+.2f}", z_crossing), "|z| ≤ 3", fmt::format("{:.2f}", 3.0 - std::fabs(z_crossing))});
  }

  // C. Exactness on grown cultures.
  r.heading("C. The spatial hash against brute force on grown cultures");
  {
    std::vector<std::vector<std::string>> t;
    std::size_t mismatched = 0;
    for (const int seed : {1, 2, 3}) {
      for (const double d : {1.0, 4.0}) {
        Scene s = culture_base();
        s.seed = static_cast<std::uint64_t>(seed);
        // A point every step (seed 3) makes ten times the segments: the brute force's
        // O(n^2) keeps that culture at the quick size.
        const bool small = o.quick || seed == 3;
        s.neurons.count = small ? 40 : 120;
        s.neurons.radius = small ? 250.0 : 300.0;
        s.steps = small ? 72 : 96;
        s.dt = 1.0;
        if (seed == 3) s.arbours->sample_length = 0.0;  // every step a point
        s.synapses = SynapseKeys{};
        s.synapses->distance = d;
        s.synapses->autapses = seed == 2;
        RunOptions ro;
        const RunResult res = run_scene(s, ro);
        const network::Segments g = network::segments_of(res.arbours, res.soma, s.neurons.soma_radius);
        const auto fast = network::find_contacts(g, d, s.synapses->autapses);
        const auto brute = network::find_contacts_brute(g, d, s.synapses->autapses);
        const network::Appositions a = network::group_appositions(g, fast, synapse_params(s));
        const network::Appositions b = network::group_appositions(g, brute, synapse_params(s));
        const bool equal = fast == brute && a.at == b.at && a.contacts == b.contacts;
        mismatched += !equal;
        t.push_back({std::to_string(seed), fmt::format("{}", d), seed == 2 ? "yes" : "no",
                     fmt::format("{}", s.arbours->sample_length), std::to_string(g.size()),
                     std::to_string(brute.size()), std::to_string(b.size()), equal ? "identical" : "DIFFERENT"});
      }
    }
    r.table({"seed", "d (µm)", "autapses", "sample length (µm)", "samples", "contacts (brute force)",
             "appositions (brute force)", "hash"},
            t, "synapses_exactness.csv");
    r.check({"the hash finds exactly the brute-force contacts and appositions: none missed, none twice",
             mismatched == 0, fmt::format("{} of {} cultures differ", mismatched, t.size()), "0",
             std::to_string(mismatched)});
  }

  // D. Convergence on grown arbours.
  r.heading("D. Appositions and connections on grown arbours as the numerics are refined");
  {
    // The same cultures (seeds) at every level: placement does not depend on the numerics,
    // and the sample length changes only where points are recorded, so successive levels
    // differ by the numerics alone (paired per seed).
    const int seeds = o.quick ? 2 : 4;
    const std::uint32_t count = 150;
    const double radius = 450.0;
    struct Level {
      std::string what;
      std::vector<double> appositions, connections;  // per seed, per neuron
      double seconds = 0;
    };
    auto measure = [&](double dt, double sample_length, const std::string& what) {
      Level l{what, {}, {}, 0.0};
      for (int seed = 1; seed <= seeds; ++seed) {
        Scene s = culture_base();
        s.seed = static_cast<std::uint64_t>(seed);
        s.neurons.count = count;
        s.neurons.radius = radius;
        s.dt = dt;
        s.steps = static_cast<std::uint32_t>(std::lround(120.0 / dt));  // 5 days
        s.arbours->sample_length = sample_length;
        s.synapses = SynapseKeys{};
        RunOptions ro;
        const auto t0 = std::chrono::steady_clock::now();
        const RunResult res = run_scene(s, ro);
        l.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        l.appositions.push_back(static_cast<double>(res.synapses.size()) / count);
        l.connections.push_back(static_cast<double>(res.synapse_connections.size()) / count);
      }
      return l;
    };
    auto mean = [](const std::vector<double>& v) { return sweep::mean_se(v).mean; };
    // The paired difference of two levels (finer minus coarser), mean ± SE over seeds.
    auto paired = [](const std::vector<double>& fine, const std::vector<double>& coarse) {
      std::vector<double> d;
      for (std::size_t k = 0; k < fine.size(); ++k) d.push_back(fine[k] - coarse[k]);
      return sweep::mean_se(d);
    };
    const std::vector<double> lengths{8, 4, 2, 1, 0.5};
    const std::vector<double> dts = o.quick ? std::vector<double>{1.0, 0.5, 0.25} : std::vector<double>{1.0, 0.5, 0.25, 0.125};
    std::vector<Level> by_sample, by_dt;
    for (const double sl : lengths) by_sample.push_back(measure(0.25, sl, fmt::format("sample length {} µm", sl)));
    for (const double dt : dts) by_dt.push_back(measure(dt, 1.0, fmt::format("dt {} h", dt)));
    std::vector<std::vector<std::string>> t;
    for (const auto* levels : {&by_sample, &by_dt})
      for (std::size_t k = 0; k < levels->size(); ++k) {
        const Level& l = (*levels)[k];
        const sweep::MeanSe a = sweep::mean_se(l.appositions), c = sweep::mean_se(l.connections);
        std::string da = "", dc = "";
        if (k > 0) {
          const sweep::MeanSe x = paired(l.appositions, (*levels)[k - 1].appositions);
          const sweep::MeanSe y = paired(l.connections, (*levels)[k - 1].connections);
          da = fmt::format("{:+.3f} ± {:.3f}", x.mean, x.se);
          dc = fmt::format("{:+.4f} ± {:.4f}", y.mean, y.se);
        }
        t.push_back({l.what, fmt::format("{:.3f} ± {:.3f}", a.mean, a.se), da,
                     fmt::format("{:.3f} ± {:.3f}", c.mean, c.se), dc, fmt::format("{:.2f}", l.seconds)});
      }
    r.table({"level", "appositions per neuron", "change from the level above (paired)", "connections per neuron",
             "change from the level above (paired)", "run time (s)"},
            t, "synapses_convergence.csv");
    // The sample length: successive changes d_k; observed order p = log2(d_(k-1) / d_k) of
    // the last two, and Richardson's estimate of the finest level's error d_k / (2^p - 1).
    const std::size_t m = by_sample.size();
    const double d1 = mean(by_sample[m - 2].appositions) - mean(by_sample[m - 3].appositions);
    const double d2 = mean(by_sample[m - 1].appositions) - mean(by_sample[m - 2].appositions);
    const double order = std::log2(d1 / d2);
    const double finest = mean(by_sample[m - 1].appositions);
    const double error = d2 / (std::pow(2.0, order) - 1.0) / finest;
    const double conn_change = std::fabs(mean(by_sample[m - 1].connections) - mean(by_sample[m - 2].connections)) /
                               mean(by_sample[m - 1].connections);
    const sweep::MeanSe dt_apps = paired(by_dt.back().appositions, by_dt[by_dt.size() - 2].appositions);
    const sweep::MeanSe dt_conn = paired(by_dt.back().connections, by_dt[by_dt.size() - 2].connections);
    const double dt_rel = std::fabs(dt_apps.mean) / mean(by_dt.back().appositions);
    const double dt_conn_rel = std::fabs(dt_conn.mean) / mean(by_dt.back().connections);
    r.text(fmt::format(
        "`scenes/culture.json` with synapses (d = 2 µm), {} neurons in a disc of radius {} µm, 5 days, the same {} "
        "seeds at every level (per-neuron means ± SE over seeds; changes are paired per seed). First the sample length "
        "(the recorded path's resolution) at dt = 0.25 h, then dt at a sample length of 1 µm. Connections settle at "
        "once. Appositions keep rising slowly as the sample length shrinks, at an observed order of {:.2f}: the "
        "neurites are worm-like chains whose heading diffuses, so the distance between an axon and a dendrite that "
        "run side by side is C¹ with a rough derivative, and a finer record resolves more of its short excursions "
        "across d (Rice's formula gives them a finite number in the limit; the approach is slow). Richardson's "
        "estimate of the finest level's error is {:.1f} %.",
        count, radius, seeds, order, 100.0 * error));
    r.check({"connections per neuron settle as the sample length is refined", conn_change <= 0.01,
             fmt::format("{:.2f} % between the two finest", 100.0 * conn_change), "≤ 1 %",
             fmt::format("{:.2f} %", 1.0 - 100.0 * conn_change)});
    r.check({"appositions converge as the sample length is refined (successive changes shrink)",
             order > 0.2 && std::isfinite(order), fmt::format("observed order {:.2f}", order), "> 0.2",
             fmt::format("{:.2f}", order - 0.2)});
    r.check({"the finest sample length's apposition count is within 5 % of its extrapolated limit",
             std::fabs(error) <= 0.05, fmt::format("{:.1f} %", 100.0 * error), "≤ 5 %",
             fmt::format("{:.1f} %", 5.0 - 100.0 * std::fabs(error))});
    r.check({"appositions per neuron converge as dt is refined (the two finest levels, paired)",
             dt_rel <= 0.02 || std::fabs(dt_apps.mean) <= 3.0 * dt_apps.se,
             fmt::format("{:+.3f} ± {:.3f} ({:.2f} %) between dt = {} and {} h", dt_apps.mean, dt_apps.se, 100.0 * dt_rel,
                         dts[dts.size() - 2], dts.back()),
             "≤ 2 %, or within 3 SE of 0", fmt::format("{:.2f} %", 2.0 - 100.0 * dt_rel)});
    r.check({"connections per neuron converge as dt is refined (the two finest levels, paired)",
             dt_conn_rel <= 0.02 || std::fabs(dt_conn.mean) <= 3.0 * dt_conn.se,
             fmt::format("{:+.4f} ± {:.4f} ({:.2f} %)", dt_conn.mean, dt_conn.se, 100.0 * dt_conn_rel),
             "≤ 2 %, or within 3 SE of 0", fmt::format("{:.2f} %", 2.0 - 100.0 * dt_conn_rel)});
  }
  r.plot("synapses.py", {"synapses_contacts.csv", "synapses_appositions.csv", "synapses_convergence.csv"}, "synapses.png",
         "Left (§A): contacts per replicate against Steiner's expectation. Middle (§B): contacts and appositions of "
         "straight neurites against the step, with the crossing term. Right (§D): appositions and connections per "
         "neuron as the sample length and dt are refined.");
}

}  // namespace axg::validate
