// `validate samplers`: uniformity of every sampler on the sphere and in the ball, for
// d = 2, 3, 5, 10 and the largest d each method reaches, with a naive (theta, phi)
// sampler as the negative control; timing against the report's Table 3; and the same
// tests on an external point file (`--points`).
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "axonguide/placement/coordinate_marginal.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/placement/placement.hpp"
#include "axonguide/placement/sampler_nd.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/points_csv.hpp"
#include "axonguide/validate/stats.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

constexpr double kFamilyAlpha = 0.01;  // family-wise error rate of a run, fixed in advance

enum class Method { kRejection, kNormal, kTrig, kCoordinate, kNaive };

const char* method_name(Method m) {
  switch (m) {
    case Method::kRejection: return "rejection";
    case Method::kNormal: return "normal";
    case Method::kTrig: return "trig";
    case Method::kCoordinate: return "coordinate";
    case Method::kNaive: return "naive (theta, phi) [control]";
  }
  return "?";
}

core::Sampler sampler_of(Method m) {
  switch (m) {
    case Method::kRejection: return core::Sampler::kRejection;
    case Method::kNormal: return core::Sampler::kNormal;
    case Method::kTrig: return core::Sampler::kTrig;
    default: return core::Sampler::kCoordinate;
  }
}

// The negative control: theta and phi uniform, which crowds the poles.
void naive_direction(core::Rng& rng, double* out) {
  const double theta = 3.141592653589793 * rng.uniform();
  const double phi = 6.283185307179586 * rng.uniform();
  out[0] = std::sin(theta) * std::cos(phi);
  out[1] = std::sin(theta) * std::sin(phi);
  out[2] = std::cos(theta);
}

// n points (sphere directions, or ball points of radius 1), row-major.
std::vector<double> draw(Method m, bool ball, int d, std::size_t n, std::uint32_t test_id, int threads) {
  std::vector<double> x(n * static_cast<std::size_t>(d));
  with_threads(threads, [&] {
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
      core::Rng rng(2014, core::Stream::kValidation, i, test_id);
      double* p = &x[i * static_cast<std::size_t>(d)];
      if (m == Method::kNaive) {
        naive_direction(rng, p);
        if (ball) {
          const double r = core::ball_radius(rng, 1.0, 3);
          for (int k = 0; k < 3; ++k) p[k] *= r;
        }
      } else {
        sampler_point(sampler_of(m), ball, d, 1.0, rng, p);
      }
    });
  });
  return x;
}

struct Case {
  Method method;
  bool ball;
  int d;
  std::size_t n;
};

struct Outcome {
  std::vector<TestResult> tests;
};

// The battery on one point set: directions (normalised ball points) get Rayleigh,
// Bingham, Gine and KS on the first and last coordinate against the exact marginal;
// ball points also KS of (r/R)^d against U(0,1).
// |x| of a d-vector, scaled by its largest component first, so that no square overflows
// (points near 1e200) or underflows to 0 (points near 1e-170).
double scaled_norm(const double* x, int d) {
  double m = 0;
  for (int k = 0; k < d; ++k) m = std::max(m, std::fabs(x[k]));
  if (m == 0 || !std::isfinite(m)) return m;
  double s = 0;
  for (int k = 0; k < d; ++k) s += (x[k] / m) * (x[k] / m);
  return m * std::sqrt(s);
}

Outcome run_battery(const std::vector<double>& x, std::size_t n, int d, bool ball, double radius) {
  Outcome o;
  std::vector<double> dir = x;
  std::vector<double> rpow;
  if (ball) {
    rpow.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double r = scaled_norm(&x[i * d], d);
      rpow[i] = std::pow(r / radius, d);
      for (int k = 0; k < d; ++k) dir[i * d + k] = r > 0 ? x[i * d + k] / r : 0.0;
    }
  }
  o.tests.push_back(rayleigh(dir.data(), n, d));
  o.tests.push_back(bingham(dir.data(), n, d));
  o.tests.push_back(gine(dir.data(), n, d));
  for (int k : {0, d - 1}) {
    if (k == 0 && d == 1) continue;
    std::vector<double> c(n);
    for (std::size_t i = 0; i < n; ++i) c[i] = dir[i * d + k];
    TestResult t = ks_cdf(c, [d](double v) { return coordinate_marginal_cdf(v, d); });
    t.name = fmt::format("KS coordinate {}", k + 1);
    o.tests.push_back(t);
    if (d == 2) break;  // both coordinates of a circle are the same test
  }
  if (ball) {
    TestResult t = ks_uniform(rpow);
    t.name = "KS (r/R)^d";
    o.tests.push_back(t);
  }
  return o;
}

std::vector<Case> cases(bool quick) {
  const std::size_t n_small = quick ? 2000 : 10000;
  const std::size_t n_large = quick ? 300 : 2000;
  std::vector<Case> out;
  for (bool ball : {false, true}) {
    for (Method m : {Method::kRejection, Method::kNormal, Method::kTrig, Method::kCoordinate}) {
      std::vector<int> dims;
      if (m == Method::kTrig) dims = {3};
      else dims = {2, 3, 5, 10};
      if (m == Method::kRejection) dims.push_back(quick ? 11 : kRejectionMaxDimension);
      if (m == Method::kNormal || m == Method::kCoordinate) dims.push_back(1000);
      for (int d : dims) out.push_back({m, ball, d, d >= 100 ? n_large : (d > 10 ? n_small / 4 : n_small)});
    }
    out.push_back({Method::kNaive, ball, 3, n_small});
  }
  return out;
}

}  // namespace

void sampler_point(core::Sampler sampler, bool ball, int d, double radius, core::Rng& rng, double* out) {
  if (d == 3) {  // placement's own calls (soma_draw, heading_draw)
    const core::Vec3 v = ball ? sample_region_point(core::RegionShape::kBall, radius, sampler, rng)
                              : sample_direction3(sampler, rng);
    out[0] = v.x, out[1] = v.y, out[2] = v.z;
  } else if (ball) {
    sample_ball(sampler, rng, d, radius, out);
  } else {
    sample_direction(sampler, rng, d, out);
  }
}

void validate_samplers(const Options& o, Report& r) {
  const std::vector<Case> all = cases(o.quick);
  std::size_t positive_tests = 0;
  std::vector<Outcome> outcomes;
  std::vector<double> seconds;
  std::uint32_t test_id = 1;
  for (const Case& c : all) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<double> x = draw(c.method, c.ball, c.d, c.n, test_id++, o.threads);
    outcomes.push_back(run_battery(x, c.n, c.d, c.ball, 1.0));
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (c.method != Method::kNaive) positive_tests += outcomes.back().tests.size();
  }
  const double threshold = kFamilyAlpha / static_cast<double>(positive_tests);
  r.text(fmt::format(
      "Every sampler draws n points from its own stream (seed 2014, `kValidation`, step = case number). Sphere "
      "cases test the directions; ball cases test the directions x/|x| and the radii. Tests: Rayleigh (mean "
      "resultant, chi2_d), Bingham (scatter matrix, chi2 with (d-1)(d+2)/2 df), Gine's G_n (all pairwise angles; "
      "asymptotic weighted chi-square law), one-sample KS of the first and last coordinate against their exact "
      "marginal, and for the ball KS of (r/R)^d against U(0,1). Criterion, fixed in advance: every p-value of a "
      "real sampler above the Bonferroni threshold {} / {} = {:.3g}; the naive control (theta and phi uniform) "
      "must have some p-value below it. Rejection stops at d = {} (acceptance V_d/2^d = {:.2g}; it refuses "
      "larger d); trig is defined for d = 3.",
      kFamilyAlpha, positive_tests, threshold, o.quick ? 11 : kRejectionMaxDimension,
      rejection_acceptance(o.quick ? 11 : kRejectionMaxDimension)));
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Case& c = all[i];
    double min_p = 1;
    std::string which;
    for (const TestResult& t : outcomes[i].tests) {
      rows.push_back({method_name(c.method), c.ball ? "ball" : "sphere", std::to_string(c.d), std::to_string(c.n), t.name,
                      num(t.statistic, 6), num(t.p_value, 4), t.note});
      if (t.p_value < min_p) min_p = t.p_value, which = t.name;
    }
    const std::string label = fmt::format("{}, {}, d = {}, n = {}", method_name(c.method), c.ball ? "ball" : "sphere", c.d, c.n);
    if (c.method == Method::kNaive)
      r.check({"negative control caught: " + label, min_p < threshold, fmt::format("min p = {:.3g} ({})", min_p, which),
               fmt::format("some p < {:.3g}", threshold), fmt::format("{:.2g}x below", threshold / std::max(min_p, 1e-300))});
    else
      r.check({"uniform: " + label, min_p >= threshold, fmt::format("min p = {:.3g} ({}); {:.2f} s", min_p, which, seconds[i]),
               fmt::format("every p >= {:.3g}", threshold), fmt::format("{:.3g}x the threshold", min_p / threshold)});
  }
  r.heading("Tests");
  r.table({"method", "region", "d", "n", "test", "statistic", "p", "note"}, rows, "sampler_tests.csv");
  {
    std::string what;
    try {
      std::vector<double> x(kRejectionMaxDimension + 1);
      core::Rng rng(1, core::Stream::kValidation, 0, 0);
      sample_direction(core::Sampler::kRejection, rng, kRejectionMaxDimension + 1, x.data());
    } catch (const InputError& e) {
      what = e.what();
    }
    r.check({fmt::format("rejection refuses d = {}", kRejectionMaxDimension + 1), !what.empty(),
             what.empty() ? "accepted" : what.substr(0, 100), "a clear refusal naming the acceptance rate", ""});
  }

  // Density of z for d = 3 directions: uniform on [-1,1] (Archimedes) for a correct sampler.
  {
    const int bins = 40;
    std::vector<std::vector<std::string>> hist(bins);
    std::vector<std::string> header{"z"};
    for (int b = 0; b < bins; ++b) hist[b].push_back(num(-1 + (b + 0.5) * 2.0 / bins));
    for (Method m : {Method::kRejection, Method::kNormal, Method::kTrig, Method::kCoordinate, Method::kNaive}) {
      const std::size_t n = 100000;
      const std::vector<double> x = draw(m, false, 3, n, 999, o.threads);
      std::vector<double> count(bins, 0);
      for (std::size_t i = 0; i < n; ++i) count[std::min(bins - 1, static_cast<int>((x[i * 3 + 2] + 1) / 2 * bins))] += 1;
      header.push_back(method_name(m));
      for (int b = 0; b < bins; ++b) hist[b].push_back(num(count[b] / n * bins / 2.0));
    }
    r.heading("The z coordinate in 3D");
    r.text("Archimedes: z of a uniform direction is uniform on [-1, 1] (density 1/2). The naive sampler piles points at "
           "the poles.");
    r.csv("sampler_z_density.csv", header, hist);
    r.plot("sampler_hist.py", {"sampler_z_density.csv"}, "sampler_z_density.png",
           "Density of z for 10^5 directions per sampler (d = 3).");
  }

  // Timing against the report's Table 3.
  {
    r.heading("Timing against the report's Table 3");
    const double table3[4][4] = {{0.25, 0.13, 0.12, 0.12}, {0.40, 0.25, 0.24, 0.24},
                                 {0.41, 0.39, 0.39, 0.40}, {0.70, 0.69, 0.68, 0.70}};
    const std::size_t sizes[4] = {500, 2500, 5000, 10000};
    std::vector<std::vector<std::string>> rows3, timing;
    const Method ms[4] = {Method::kRejection, Method::kNormal, Method::kTrig, Method::kCoordinate};
    for (int k = 0; k < 4; ++k) {
      std::vector<std::string> row{std::to_string(sizes[k])};
      for (int m = 0; m < 4; ++m) {
        Scene s;
        s.neurons.count = sizes[k];
        s.neurons.radius = 2.5 * std::cbrt(sizes[k] / 100.0);
        s.neurons.sampler = sampler_of(ms[m]);
        const auto t0 = std::chrono::steady_clock::now();
        with_threads(o.threads, [&] { place_neurons(s); });
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        row.push_back(fmt::format("{} / {:.4f}", table3[k][m], t));
      }
      rows3.push_back(row);
    }
    r.text("Placing N neurons (positions, overlap rejection and headings) at the report's density; each cell is "
           "report seconds / our seconds. The report timed its four methods on a 2011 desktop CPU (Table 2, "
           "CAGE038) including its own overheads; ours run on this machine's cores.");
    r.table({"N", "rejection", "normal", "trig", "coordinate"}, rows3, "table3.csv");
    std::vector<std::size_t> ns{500, 5000, 50000, 500000};
    if (!o.quick) ns.push_back(1000000);
    for (Method m : ms)
      for (std::size_t n : ns) {
        const std::size_t nn = m == Method::kCoordinate ? std::min<std::size_t>(n, 100000) : n;
        const auto t0 = std::chrono::steady_clock::now();
        draw(m, false, 3, nn, 555, o.threads);
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        timing.push_back({method_name(m), std::to_string(nn), num(t)});
      }
    r.text("Directions alone, from 500 to 10^6 points (coordinate up to 10^5: each of its points needs d - 1 "
           "incomplete-beta inversions):");
    r.table({"method", "n", "seconds"}, timing, "sampler_timing.csv");
    r.plot("sampler_timing.py", {"sampler_timing.csv"}, "sampler_timing.png",
           "Seconds to draw n directions in 3D per sampler; triangles: the report's Table 3 (trig column).");
  }
}

void validate_points_file(const Options& o, Report& r) {
  std::ifstream in(o.points_file);
  if (!in) throw InputError(fmt::format("--points {}: cannot open", o.points_file));
  const PointRows points = read_points_csv(in, fmt::format("--points {}", o.points_file));
  const std::vector<double>& x = points.x;
  const std::size_t n = points.n;
  const int d = points.d;
  if (n < 10 || d < 2) throw InputError(fmt::format("--points {}: need at least 10 points of dimension >= 2 (found {} of {})",
                                                    o.points_file, n, d));
  bool unit = true;
  double max_r = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double norm = scaled_norm(&x[i * d], d);
    unit = unit && std::fabs(norm - 1) < 1e-6;
    max_r = std::max(max_r, norm);
  }
  if (!std::isfinite(max_r))
    throw InputError(fmt::format("--points {}: a point's length |x| is beyond the largest double", o.points_file));
  if (!unit && max_r > o.radius * (1 + 1e-12))
    throw InputError(fmt::format("--points {}: points are not unit vectors and reach |x| = {} beyond --radius {}",
                                 o.points_file, max_r, o.radius));
  const Outcome out = run_battery(x, n, d, !unit, o.radius);
  const double threshold = kFamilyAlpha / static_cast<double>(out.tests.size());
  r.text(fmt::format("{} points of dimension {} from `{}`, treated as {}. Criterion: every p-value above {} / {} = {:.3g}.", n,
                     d, o.points_file, unit ? "directions on the sphere" : fmt::format("points in the ball of radius {}", o.radius),
                     kFamilyAlpha, out.tests.size(), threshold));
  std::vector<std::vector<std::string>> rows;
  for (const TestResult& t : out.tests) {
    rows.push_back({t.name, num(t.statistic, 6), num(t.p_value, 4), t.note});
    r.check({t.name, t.p_value >= threshold, fmt::format("p = {:.3g}", t.p_value), fmt::format("p >= {:.3g}", threshold),
             fmt::format("{:.3g}x the threshold", t.p_value / threshold)});
  }
  r.table({"test", "statistic", "p", "note"}, rows, "points_tests.csv");
}

}  // namespace axg::validate
