#include "axonguide/study/assay.hpp"

#include <cmath>
#include <limits>

#include "axonguide/core/pmath.hpp"
#include "axonguide/model/cues.hpp"
#include "axonguide/placement/placement.hpp"

namespace axg::assay {

using core::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Vec3 unit(Vec3 v) {
  const double n = std::sqrt(core::norm2(v));
  return n > 0 ? v * (1.0 / n) : Vec3{1.0, 0.0, 0.0};
}

// The sector of angle atan2(y, x) in [0, 2π), kAngleBins equal sectors from θ = 0.
int sector(double x, double y) {
  double t = std::atan2(y, x);
  if (t < 0) t += 2.0 * kPi;
  int j = static_cast<int>(t * (kAngleBins / (2.0 * kPi)));
  return j >= kAngleBins ? kAngleBins - 1 : j;
}

// Standard error of a ratio of sums Σa/Σb over n items (delta method).
double ratio_se(const std::vector<double>& a, const std::vector<double>& b, double ratio) {
  const std::size_t n = a.size();
  if (n < 2) return kNaN;
  double sb = 0, ss = 0;
  for (std::size_t i = 0; i < n; ++i) sb += b[i];
  const double mb = sb / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = a[i] - ratio * b[i];
    ss += r * r;
  }
  if (mb == 0) return kNaN;
  return std::sqrt(ss / static_cast<double>(n - 1) / static_cast<double>(n)) / mb;
}

// outgrowth and outgrowth_bias from the least-squares line o = R0 + R1 u (assay.hpp).
void radial_outgrowth(const std::vector<double>& o, const std::vector<double>& u, Metrics& m) {
  const std::size_t n = o.size();
  m.outgrowth = m.outgrowth_se = m.outgrowth_bias = m.outgrowth_bias_se = kNaN;
  if (n < 3) return;
  const double nn = static_cast<double>(n);
  double so = 0, su = 0;
  for (std::size_t i = 0; i < n; ++i) so += o[i], su += u[i];
  const double mo = so / nn, mu = su / nn;
  double suu = 0, suo = 0;
  for (std::size_t i = 0; i < n; ++i) {
    suu += (u[i] - mu) * (u[i] - mu);
    suo += (u[i] - mu) * (o[i] - mo);
  }
  const double r1 = suu > 0 ? suo / suu : 0.0;
  const double r0 = mo - r1 * mu;
  double ss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = o[i] - r0 - r1 * u[i];
    ss += e * e;
  }
  const double s2 = ss / (nn - 2.0);
  // Var(R0) = s2 (1/n + mu^2 / Suu), Var(R1) = s2 / Suu, Cov(R0, R1) = -mu s2 / Suu.
  const double v1 = suu > 0 ? s2 / suu : kNaN;
  const double v0 = s2 / nn + mu * mu * (suu > 0 ? s2 / suu : 0.0);
  const double c01 = -mu * (suu > 0 ? s2 / suu : 0.0);
  m.outgrowth = r0;
  m.outgrowth_se = std::sqrt(v0);
  if (r0 != 0) {
    const double b = r1 / r0;
    m.outgrowth_bias = b;
    m.outgrowth_bias_se = std::sqrt((v1 - 2.0 * b * c01 + b * b * v0) / (r0 * r0));
  }
}

}  // namespace

std::vector<core::CueParams> reference_cues(const Scene& scene) {
  if (scene.uses_cues()) return make_cues(scene);
  Scene s = scene;
  s.guidance.model = GuidanceModel::kSnr;
  return make_cues(s);
}

Geometry explant_geometry(const Scene& scene, const std::vector<core::CueParams>& cues) {
  Geometry g;
  const auto& pops = scene.neurons.populations;
  g.end = pops.empty() ? scene.neurons.count : pops[0].count;
  g.center = pops.empty() ? Vec3{0.0, 0.0, 0.0} : pops[0].center;
  g.has_target = pops.size() > 1;
  if (g.has_target) g.target_center = pops[1].center;

  Vec3 axis{1.0, 0.0, 0.0};
  if (scene.cues.field == FieldKind::kImposed) {
    axis = unit(scene.cues.imposed.direction);
  } else if (!cues.empty()) {
    std::size_t pick = 0;
    for (std::size_t k = cues.size(); k-- > 0;)
      if (cues[k].sign > 0) pick = k;
    const Vec3 d = cues[pick].position - g.center;
    if (core::norm2(d) > 0) axis = unit(d);
  }
  // The microscope looks along z unless the gradient does, then along x.
  const Vec3 view = std::fabs(axis.z) < 0.9 ? Vec3{0.0, 0.0, 1.0} : Vec3{1.0, 0.0, 0.0};
  g.axis = axis;
  g.up = unit(axis - view * core::dot(axis, view));
  g.across = unit(core::cross(g.up, view));
  return g;
}

Metrics measure(const Scene& scene, const std::vector<Vec3>& soma, const NeuronState& neurons,
                const std::vector<core::CueParams>& cues) {
  const Geometry g = explant_geometry(scene, cues);
  Metrics m;
  std::array<double, kAngleBins> sin_centre{};
  for (int j = 0; j < kAngleBins; ++j) sin_centre[j] = core::pm::sin((j + 0.5) * (2.0 * kPi / kAngleBins));

  std::vector<double> rho, rho_sin, rho_sign, turn, radial, cosine;
  std::uint64_t connected = 0, exited = 0, to_target = 0, explant = 0;
  const auto& pops = scene.neurons.populations;
  for (std::uint64_t i = g.first; i < g.end; ++i) {
    ++explant;
    if (neurons.status[i] == core::AxonStatus::kConnected) {
      ++connected;
      if (!pops.empty() && scene.neurons.population_of(neurons.target[i]) != 0) ++to_target;
    }
    if (neurons.status[i] == core::AxonStatus::kExited) ++exited;
    if (!(neurons.length[i] > 0)) continue;
    const Vec3 d = neurons.tip[i] - g.center;
    const double x = core::dot(d, g.across), y = core::dot(d, g.up);
    const double r = std::sqrt(x * x + y * y);
    const int j = sector(x, y);
    m.profile[j] += r;
    ++m.profile_axons[j];
    rho.push_back(r);
    rho_sin.push_back(2.0 * r * sin_centre[j]);
    rho_sign.push_back(y > 0 ? r : (y < 0 ? -r : 0.0));
    const double reach = std::sqrt(core::norm2(d));
    radial.push_back(reach - std::sqrt(core::norm2(soma[i] - g.center)) - scene.neurons.soma_radius);
    cosine.push_back(reach > 0 ? core::dot(d, g.axis) / reach : 0.0);

    // Turning: the signed angle in the plane from the initial heading to the net
    // displacement of the tip, positive toward the gradient.
    const Vec3 h0 = initial_heading(scene, i, soma[i]);
    const Vec3 start = soma[i] + h0 * scene.neurons.soma_radius;
    const Vec3 dd = neurons.tip[i] - start;
    const double ax = core::dot(h0, g.across), ay = core::dot(h0, g.up);
    const double bx = core::dot(dd, g.across), by = core::dot(dd, g.up);
    const double phi = std::atan2(ax * by - ay * bx, ax * bx + ay * by) * (ax >= 0 ? 1.0 : -1.0);
    turn.push_back(phi * (180.0 / kPi));
    int k = static_cast<int>((phi + kPi) * (kTurningBins / (2.0 * kPi)));
    m.turning[k < 0 ? 0 : (k >= kTurningBins ? kTurningBins - 1 : k)] += 1;
  }
  m.axons = rho.size();
  const double n = static_cast<double>(m.axons);
  double sum = 0, sum_sin = 0, sum_sign = 0, sum_turn = 0;
  for (std::size_t i = 0; i < rho.size(); ++i) {
    sum += rho[i];
    sum_sin += rho_sin[i];
    sum_sign += rho_sign[i];
    sum_turn += turn[i];
  }
  for (int j = 0; j < kAngleBins; ++j) m.profile[j] = n > 0 ? m.profile[j] * (kAngleBins / n) : 0.0;
  m.mean_outgrowth = n > 0 ? sum / n : kNaN;
  m.bias = sum > 0 ? sum_sin / sum : kNaN;
  m.bias_se = sum > 0 ? ratio_se(rho_sin, rho, m.bias) : kNaN;
  m.guidance_ratio = sum > 0 ? sum_sign / sum : kNaN;
  m.guidance_ratio_se = sum > 0 ? ratio_se(rho_sign, rho, m.guidance_ratio) : kNaN;
  m.mean_turning_deg = n > 0 ? sum_turn / n : kNaN;
  if (n > 1) {
    double ss = 0;
    for (double t : turn) ss += (t - m.mean_turning_deg) * (t - m.mean_turning_deg);
    m.turning_se_deg = std::sqrt(ss / (n - 1) / n);
  } else {
    m.turning_se_deg = kNaN;
  }
  radial_outgrowth(radial, cosine, m);
  const double ne = static_cast<double>(explant);
  m.connected_fraction = ne > 0 ? static_cast<double>(connected) / ne : kNaN;
  m.exited_fraction = ne > 0 ? static_cast<double>(exited) / ne : kNaN;
  m.target_fraction = g.has_target && ne > 0 ? static_cast<double>(to_target) / ne : kNaN;
  m.crossing_fraction = kNaN;
  if (g.has_target) {
    const Vec3 mid = (g.center + g.target_center) * 0.5;
    const Vec3 u = unit(g.target_center - g.center);
    std::uint64_t crossed = 0, total = 0;
    const std::uint64_t end1 = g.end + pops[1].count;
    for (std::uint64_t i = 0; i < end1; ++i) {
      const double side = core::dot(neurons.tip[i] - mid, u);
      crossed += i < g.end ? (side > 0) : (side < 0);
      ++total;
    }
    m.crossing_axons = total;
    m.crossing_fraction = static_cast<double>(crossed) / static_cast<double>(total);
  }
  std::uint64_t near_a = 0, near_r = 0;
  bool has_a = false, has_r = false;
  const double reach2 = 9.0 * scene.guidance.sensing_radius * scene.guidance.sensing_radius;
  for (const auto& c : cues) (c.sign > 0 ? has_a : has_r) = true;
  for (std::size_t i = 0; i < neurons.size(); ++i) {
    bool a = false, r = false;
    for (const auto& c : cues)
      if (core::norm2(neurons.tip[i] - c.position) <= reach2) (c.sign > 0 ? a : r) = true;
    near_a += a;
    near_r += r;
  }
  const double all = static_cast<double>(neurons.size());
  m.near_attractant_fraction = has_a && all > 0 ? static_cast<double>(near_a) / all : kNaN;
  m.near_repellent_fraction = has_r && all > 0 ? static_cast<double>(near_r) / all : kNaN;
  return m;
}

const std::vector<std::string>& scalar_metric_names() {
  static const std::vector<std::string> names{
      "axons",          "bias",           "bias_se",          "guidance_ratio", "guidance_ratio_se",
      "mean_outgrowth", "mean_turning_deg", "turning_se_deg", "connected_fraction", "exited_fraction",
      "target_fraction", "crossing_fraction", "near_attractant_fraction", "near_repellent_fraction",
      "outgrowth",      "outgrowth_se",   "outgrowth_bias",   "outgrowth_bias_se"};
  return names;
}

std::vector<std::pair<std::string, double>> scalar_metrics(const Metrics& m) {
  const double values[] = {static_cast<double>(m.axons), m.bias, m.bias_se, m.guidance_ratio,
                           m.guidance_ratio_se, m.mean_outgrowth, m.mean_turning_deg, m.turning_se_deg,
                           m.connected_fraction, m.exited_fraction, m.target_fraction, m.crossing_fraction,
                           m.near_attractant_fraction, m.near_repellent_fraction, m.outgrowth, m.outgrowth_se,
                           m.outgrowth_bias, m.outgrowth_bias_se};
  std::vector<std::pair<std::string, double>> out;
  const auto& names = scalar_metric_names();
  for (std::size_t k = 0; k < names.size(); ++k) out.emplace_back(names[k], values[k]);
  return out;
}

std::pair<double, double> wilson_interval(double k, double n) {
  if (!(n > 0)) return {kNaN, kNaN};
  const double z = 1.959963984540054, p = k / n, z2n = z * z / n;
  const double centre = (p + z2n / 2.0) / (1.0 + z2n);
  const double half = z * std::sqrt(p * (1.0 - p) / n + z2n / (4.0 * n)) / (1.0 + z2n);
  return {centre - half, centre + half};
}

}  // namespace axg::assay
