// Calibration on morphometric data (docs/methods.md §12.8).
#include "axonguide/study/morphometry_fit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "axonguide/core/random.hpp"
#include "axonguide/core/sampler.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/morphology/morphometry.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/support/error.hpp"

namespace axg::morphofit {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr std::size_t kNeuronStats = 6;  // the first six of statistic_names(): per neuron
constexpr double kShrink = 0.05;         // the correlation matrices' shrinkage toward the identity
constexpr double kStep = 0.05;           // forward-difference step in log parameter

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ',')) out.push_back(f);
  return out;
}

int statistic_index(const std::string& name) {
  const auto& names = morphology::statistic_names();
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

NeuriteKeys& neurite_of(Scene& s, const std::string& name) {
  if (!s.arbours) throw InputError("fit: the scene has no arbours section: a morphometric fit needs an arbour scene");
  return name.rfind("axon.", 0) == 0 ? s.arbours->axon : s.arbours->dendrites;
}

// The fittable key `key` of the neurite key table (model/arbours.hpp), or nullptr.
const NeuriteKey* fittable_key(const std::string& key) {
  for (const NeuriteKey& k : neurite_key_table())
    if (k.fittable && key == k.name) return &k;
  return nullptr;
}

// "B, E, S, tau, ...": the fittable keys, in the table's order.
std::string fittable_list() {
  std::string out;
  for (const NeuriteKey& k : neurite_key_table())
    if (k.fittable) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

std::string key_of(const std::string& name) { return name.substr(name.find('.') + 1); }

}  // namespace

const std::vector<std::string>& parameter_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const char* n : {"axon.", "dendrites."})
      for (const NeuriteKey& k : neurite_key_table())
        if (k.fittable) v.push_back(std::string(n) + k.name);
    return v;
  }();
  return names;
}

double get_parameter(const Scene& s, const std::string& name) {
  Scene& m = const_cast<Scene&>(s);
  NeuriteKeys& n = neurite_of(m, name);
  const NeuriteKey* k = fittable_key(key_of(name));
  if (k == nullptr)
    throw InputError(fmt::format("fit: --param {}: not a fittable arbour parameter (one of axon.X or dendrites.X, X in "
                                 "{})",
                                 name, fittable_list()));
  if (k->optional) {
    if (!(n.*k->optional))
      throw InputError(fmt::format("fit: --param {}: the scene's {} is null (infinite); give it a finite starting "
                                   "value to fit it",
                                   name, k->name));
    return *(n.*k->optional);
  }
  return n.*k->number;
}

void set_parameter(Scene& s, const std::string& name, double value) {
  NeuriteKeys& n = neurite_of(s, name);
  const NeuriteKey* k = fittable_key(key_of(name));
  if (k == nullptr) return;
  if (k->optional) n.*k->optional = value;
  else n.*k->number = value;
}

bool is_morphometric_data(const std::string& path) {
  // The first line that is not a comment, read at most 64 KiB in (a device or a huge file
  // without line breaks is not read whole; the fit's own reader refuses it).
  std::ifstream in(path, std::ios::binary);
  std::string head(65536, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(0, in.gcount())));
  std::istringstream lines(head);
  std::string line;
  while (std::getline(lines, line))
    if (!line.empty() && line[0] != '#') return line.rfind("statistic,age_days,n,mean,sd,se", 0) == 0;
  return false;
}

std::vector<DataRow> load_data(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("fit: cannot read the data file {}", path));
  std::vector<DataRow> out;
  std::string line;
  int number = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    const std::vector<std::string> f = split(line);
    auto bad = [&](const std::string& why) {
      throw InputError(fmt::format("fit: {} line {}: {}", path, number, why));
    };
    if (f.size() < 6) bad("fewer than 6 fields (statistic, age_days, n, mean, sd, se)");
    DataRow r;
    r.statistic = f[0];
    if (statistic_index(r.statistic) < 0) bad(fmt::format("'{}' is not a statistic axonguide morphometry computes", f[0]));
    try {
      r.age_days = std::stod(f[1]);
      r.n = std::stod(f[2]);
      r.mean = std::stod(f[3]);
      r.sd = std::stod(f[4]);
      r.se = std::stod(f[5]);
    } catch (const std::exception&) {
      bad("a field that is not a number");
    }
    if (!(r.age_days > 0) || !std::isfinite(r.mean) || !(r.se > 0) || !std::isfinite(r.se))
      bad("age_days and se must be positive and mean finite");
    out.push_back(r);
  }
  if (out.empty()) throw InputError(fmt::format("fit: {} holds no data rows", path));
  return out;
}

namespace {

// The scene run to `days`: steps = days / dt in the scene's time unit.
Scene at_age(const Scene& base, double days) {
  const std::string& u = base.units.time;
  const double per_day = u == "h" ? 24.0 : u == "min" ? 1440.0 : u == "s" ? 86400.0 : 0.0;
  if (per_day == 0.0)
    throw InputError("fit: a morphometric fit needs the scene's time in physical units (units.time h, min or s)");
  Scene s = base;
  s.steps = static_cast<std::uint32_t>(std::llround(days * per_day / base.dt));
  if (s.steps == 0) throw InputError(fmt::format("fit: an age of {} days is under one step of dt = {}", days, base.dt));
  s.output = Scene::Output{};
  s.output.graphml = false;
  s.analysis.bfs_sources.clear();
  s.analysis.components = false;
  if (s.arbours->axon.tau.has_value() == false && s.arbours->axon.period.has_value() == false)
    s.arbours->axon.period = static_cast<double>(base.steps) * base.dt;  // B over the scene's own period
  if (s.arbours->dendrites.tau.has_value() == false && s.arbours->dendrites.period.has_value() == false)
    s.arbours->dendrites.period = static_cast<double>(base.steps) * base.dt;
  return s;
}

morphology::Morphology to_morphology(const RunResult& r, std::size_t i) {
  morphology::Morphology m;
  m.name = std::to_string(i);
  const double um = r.scene.units.micrometres();
  const core::Vec3 soma = r.soma[i];
  m.samples.push_back({1, 1, soma.x * um, soma.y * um, soma.z * um, r.scene.neurons.soma_radius * um, -1});
  const std::vector<morphology::ArbourSample> s = morphology::arbour_samples(r.arbours[i]);
  for (std::size_t j = 0; j < s.size(); ++j)
    m.samples.push_back({static_cast<std::int64_t>(j + 2), s[j].type, s[j].pos.x * um, s[j].pos.y * um,
                         s[j].pos.z * um, 0.0, static_cast<std::int64_t>(s[j].parent) - 1});  // parents as indices, as read_swc stores them
  return m;
}

// Every neuron of every seed, measured.
std::vector<morphology::NeuronStats> grow(const Scene& s, const std::vector<std::uint64_t>& seeds) {
  const morphology::Projection projection =
      s.neurons.shape == RegionShape::kDisc ? morphology::Projection::kXY : morphology::Projection::kNone;
  std::vector<morphology::NeuronStats> out;
  for (const std::uint64_t seed : seeds) {
    Scene t = s;
    t.seed = seed;
    const RunResult r = run_scene(t, RunOptions{});
    for (std::size_t i = 0; i < r.arbours.size(); ++i) out.push_back(morphology::measure(to_morphology(r, i), projection));
  }
  return out;
}

// Per-neuron and per-dendrite vectors of the statistics, in statistic_names() order.
std::vector<double> neuron_vector(const morphology::NeuronStats& n) {
  return {n.axon.total_length,
          static_cast<double>(n.axon.branch_points),
          static_cast<double>(n.axon.terminal_segments),
          n.axon.mean_terminal_segment_length,
          n.axon.mean_intermediate_segment_length,
          static_cast<double>(n.dendrites.size())};
}
std::vector<double> dendrite_vector(const morphology::NeuriteStats& d) {
  return {d.total_length, static_cast<double>(d.branch_points), static_cast<double>(d.terminal_segments),
          d.mean_terminal_segment_length, d.mean_intermediate_segment_length};
}

// The correlation matrix of the listed components over the vectors, shrunk toward I.
std::vector<double> correlation(const std::vector<std::vector<double>>& v, const std::vector<int>& comp) {
  const std::size_t k = comp.size(), n = v.size();
  std::vector<double> mean(k, 0.0), c(k * k, 0.0);
  for (const auto& x : v)
    for (std::size_t a = 0; a < k; ++a) mean[a] += x[comp[a]] / static_cast<double>(n);
  for (const auto& x : v)
    for (std::size_t a = 0; a < k; ++a)
      for (std::size_t b = 0; b < k; ++b) c[a * k + b] += (x[comp[a]] - mean[a]) * (x[comp[b]] - mean[b]);
  std::vector<double> r(k * k, 0.0);
  for (std::size_t a = 0; a < k; ++a)
    for (std::size_t b = 0; b < k; ++b) {
      const double d = std::sqrt(c[a * k + a] * c[b * k + b]);
      const double rho = a == b ? 1.0 : (d > 0 ? c[a * k + b] / d : 0.0);
      r[a * k + b] = (1.0 - kShrink) * rho + (a == b ? kShrink : 0.0);
    }
  return r;
}

// Lower Cholesky factor of a k x k symmetric positive definite matrix.
std::vector<double> cholesky(std::vector<double> a, std::size_t k) {
  for (std::size_t j = 0; j < k; ++j) {
    double d = a[j * k + j];
    for (std::size_t m = 0; m < j; ++m) d -= a[j * k + m] * a[j * k + m];
    if (!(d > 0)) {
      std::string m;
      for (std::size_t i = 0; i < k * k; ++i) m += fmt::format("{}{:.3g}", i ? " " : "", a[i]);
      throw RunError(fmt::format("fit: a correlation matrix of the statistics is not positive definite ({} x {}: {})", k, k, m));
    }
    a[j * k + j] = std::sqrt(d);
    for (std::size_t i = j + 1; i < k; ++i) {
      double s = a[i * k + j];
      for (std::size_t m = 0; m < j; ++m) s -= a[i * k + m] * a[j * k + m];
      a[i * k + j] = s / a[j * k + j];
    }
    for (std::size_t m = j + 1; m < k; ++m) a[j * k + m] = 0.0;
  }
  return a;
}

// One block of correlated residuals: data row indices and the Cholesky factor of their R.
struct Block {
  std::vector<std::size_t> rows;
  std::vector<double> chol;
};

class Problem {
 public:
  Problem(const Scene& base, const std::vector<DataRow>& data, const Options& o) : base_(base), data_(data), o_(o) {
    for (const DataRow& d : data_)
      if (std::find(ages_.begin(), ages_.end(), d.age_days) == ages_.end()) ages_.push_back(d.age_days);
    std::sort(ages_.begin(), ages_.end());
  }

  // Model rows aligned with the data (and, when `blocks` is asked, the correlation blocks).
  std::vector<ModelRow> model(const Scene& s, std::vector<Block>* blocks) {
    ++evaluations_;
    std::vector<ModelRow> out(data_.size());
    for (const double age : ages_) {
      const std::vector<morphology::NeuronStats> neurons = grow(at_age(s, age), o_.seeds);
      const std::vector<morphology::Row> rows = morphology::population(neurons);
      for (std::size_t i = 0; i < data_.size(); ++i) {
        if (data_[i].age_days != age) continue;
        const morphology::Row& m = rows[static_cast<std::size_t>(statistic_index(data_[i].statistic))];
        out[i] = {data_[i].statistic, age, static_cast<double>(m.n), m.mean, m.se};
      }
      if (!blocks) continue;
      std::vector<std::vector<double>> nv, dv;
      for (const auto& n : neurons) {
        if (n.has_axon) nv.push_back(neuron_vector(n));
        for (const auto& d : n.dendrites) dv.push_back(dendrite_vector(d));
      }
      for (int group = 0; group < 2; ++group) {
        Block b;
        std::vector<int> comp;
        for (std::size_t i = 0; i < data_.size(); ++i) {
          if (data_[i].age_days != age) continue;
          const int k = statistic_index(data_[i].statistic);
          if ((k < static_cast<int>(kNeuronStats)) != (group == 0)) continue;
          b.rows.push_back(i);
          comp.push_back(group == 0 ? k : k - static_cast<int>(kNeuronStats));
        }
        if (b.rows.empty()) continue;
        const auto& v = group == 0 ? nv : dv;
        b.chol = v.size() > comp.size() + 1 ? cholesky(correlation(v, comp), comp.size())
                                            : cholesky(identity(comp.size()), comp.size());
        blocks->push_back(std::move(b));
      }
    }
    return out;
  }

  std::vector<double> z(const std::vector<ModelRow>& m) const {
    std::vector<double> out(m.size());
    for (std::size_t i = 0; i < m.size(); ++i)
      out[i] = (m[i].mean - data_[i].mean) / std::sqrt(data_[i].se * data_[i].se + m[i].se * m[i].se);
    for (std::size_t i = 0; i < m.size(); ++i)
      if (!std::isfinite(out[i]))
        throw RunError(fmt::format("fit: the model's {} at {} days is not a number (mean {}, se {}, n {})",
                                   data_[i].statistic, data_[i].age_days, m[i].mean, m[i].se, m[i].n));
    return out;
  }

  // Whitened residuals: L^-1 z within each block.
  std::vector<double> whiten(const std::vector<double>& z) const {
    std::vector<double> w;
    for (const Block& b : blocks_) {
      const std::size_t k = b.rows.size();
      std::vector<double> y(k);
      for (std::size_t i = 0; i < k; ++i) {
        double s = z[b.rows[i]];
        for (std::size_t m = 0; m < i; ++m) s -= b.chol[i * k + m] * y[m];
        y[i] = s / b.chol[i * k + i];
      }
      w.insert(w.end(), y.begin(), y.end());
    }
    return w;
  }

  std::vector<double> residuals(const Scene& s) { return whiten(z(model(s, nullptr))); }
  void set_blocks(std::vector<Block> b) { blocks_ = std::move(b); }
  int evaluations() const { return evaluations_; }

  static std::vector<double> identity(std::size_t k) {
    std::vector<double> r(k * k, 0.0);
    for (std::size_t i = 0; i < k; ++i) r[i * k + i] = 1.0;
    return r;
  }

 private:
  const Scene& base_;
  const std::vector<DataRow>& data_;
  const Options& o_;
  std::vector<double> ages_;
  std::vector<Block> blocks_;
  int evaluations_ = 0;
};

double sum_squares(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return s;
}

// Solves (A + lambda diag A) x = b for a p x p A (Gaussian elimination with pivoting).
std::vector<double> solve(std::vector<double> a, std::vector<double> b, std::size_t p) {
  for (std::size_t c = 0; c < p; ++c) {
    std::size_t piv = c;
    for (std::size_t r = c + 1; r < p; ++r)
      if (std::fabs(a[r * p + c]) > std::fabs(a[piv * p + c])) piv = r;
    for (std::size_t k = 0; k < p; ++k) std::swap(a[c * p + k], a[piv * p + k]);
    std::swap(b[c], b[piv]);
    if (a[c * p + c] == 0.0) throw RunError("fit: the normal equations are singular (a parameter the data do not move)");
    for (std::size_t r = c + 1; r < p; ++r) {
      const double f = a[r * p + c] / a[c * p + c];
      for (std::size_t k = c; k < p; ++k) a[r * p + k] -= f * a[c * p + k];
      b[r] -= f * b[c];
    }
  }
  std::vector<double> x(p);
  for (std::size_t c = p; c-- > 0;) {
    double s = b[c];
    for (std::size_t k = c + 1; k < p; ++k) s -= a[c * p + k] * x[k];
    x[c] = s / a[c * p + c];
  }
  return x;
}

std::vector<double> invert(const std::vector<double>& a, std::size_t p) {
  std::vector<double> inv(p * p);
  for (std::size_t c = 0; c < p; ++c) {
    std::vector<double> e(p, 0.0);
    e[c] = 1.0;
    const std::vector<double> x = solve(a, e, p);
    for (std::size_t r = 0; r < p; ++r) inv[r * p + c] = x[r];
  }
  return inv;
}

struct Fitter {
  Problem& problem;
  const Scene& base;
  std::vector<Parameter> params;
  std::vector<double> lo, hi;  // log bounds
  std::function<void(const std::string&)> progress;

  Scene scene_at(const std::vector<double>& theta) const {
    Scene s = base;
    for (std::size_t k = 0; k < params.size(); ++k) set_parameter(s, params[k].name, std::exp(theta[k]));
    return s;
  }
  std::vector<double> clamp(std::vector<double> t) const {
    for (std::size_t k = 0; k < t.size(); ++k) t[k] = std::min(hi[k], std::max(lo[k], t[k]));
    return t;
  }
  std::vector<double> jacobian(const std::vector<double>& theta, const std::vector<double>& r0,
                               const std::vector<bool>& free) {
    const std::size_t p = theta.size(), d = r0.size();
    std::vector<double> j(d * p, 0.0);
    for (std::size_t k = 0; k < p; ++k) {
      if (!free[k]) continue;
      std::vector<double> t = theta;
      const double h = t[k] + kStep <= hi[k] ? kStep : -kStep;
      t[k] += h;
      const std::vector<double> r = problem.residuals(scene_at(t));
      for (std::size_t i = 0; i < d; ++i) j[i * p + k] = (r[i] - r0[i]) / h;
    }
    return j;
  }
  // Levenberg-Marquardt over the free parameters; returns the chi^2 and (through jtj) the
  // last J^T J.
  double minimise(std::vector<double>& theta, const std::vector<bool>& free, int iterations, std::vector<double>* jtj_out) {
    const std::size_t p = theta.size();
    std::vector<double> r = problem.residuals(scene_at(theta));
    double chi2 = sum_squares(r), lambda = 1e-2;
    std::vector<double> jtj(p * p, 0.0);
    for (int it = 0; it < iterations; ++it) {
      const std::vector<double> j = jacobian(theta, r, free);
      const std::size_t d = r.size();
      std::vector<double> g(p, 0.0);
      std::fill(jtj.begin(), jtj.end(), 0.0);
      for (std::size_t i = 0; i < d; ++i)
        for (std::size_t a = 0; a < p; ++a) {
          g[a] -= j[i * p + a] * r[i];
          for (std::size_t b = 0; b < p; ++b) jtj[a * p + b] += j[i * p + a] * j[i * p + b];
        }
      for (std::size_t a = 0; a < p; ++a)
        if (!free[a]) {
          for (std::size_t b = 0; b < p; ++b) jtj[a * p + b] = jtj[b * p + a] = 0.0;
          jtj[a * p + a] = 1.0;
          g[a] = 0.0;
        }
      bool improved = false;
      for (int tries = 0; tries < 5 && !improved; ++tries) {
        std::vector<double> m = jtj;
        for (std::size_t a = 0; a < p; ++a) m[a * p + a] *= 1.0 + lambda;
        const std::vector<double> step = solve(m, g, p);
        std::vector<double> t = theta;
        for (std::size_t a = 0; a < p; ++a) t[a] += std::max(-1.0, std::min(1.0, step[a]));
        t = clamp(t);
        const std::vector<double> rt = problem.residuals(scene_at(t));
        const double c = sum_squares(rt);
        if (c < chi2) {
          const double gain = chi2 - c;
          theta = t;
          r = rt;
          chi2 = c;
          lambda = std::max(1e-4, lambda / 3.0);
          improved = true;
          if (progress) progress(fmt::format("fit: iteration {}, chi2 {:.2f}", it + 1, chi2));
          if (gain < 1e-3 * chi2) it = iterations;  // converged
        } else {
          lambda *= 4.0;
        }
      }
      if (!improved) break;
    }
    if (jtj_out) *jtj_out = jtj;
    return chi2;
  }
};

}  // namespace

Result fit(const Scene& base, const std::vector<DataRow>& data, const Options& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!base.arbours) throw InputError("fit: the scene has no arbours section: a morphometric fit needs an arbour scene");
  std::vector<Parameter> params = options.parameters;
  if (params.empty())
    for (const char* n : {"axon.B", "axon.E", "axon.tau", "axon.v0", "axon.F", "dendrites.B", "dendrites.v0",
                          "dendrites.stem_rate"})
      params.push_back({n, 0, 0});
  Problem problem(base, data, options);
  Fitter f{problem, base, params, {}, {}, options.on_progress};
  std::vector<double> theta;
  for (const Parameter& p : params) {
    const double v = get_parameter(base, p.name);
    if (!(v > 0)) throw InputError(fmt::format("fit: --param {}: its starting value {} must be positive (fitted in log)", p.name, v));
    theta.push_back(std::log(v));
    f.lo.push_back(p.lo > 0 ? std::log(p.lo) : std::log(v) - std::log(100.0));
    f.hi.push_back(p.hi > 0 ? std::log(p.hi) : std::log(v) + std::log(100.0));
  }
  const std::vector<double> start = theta;
  // The correlation blocks at the starting parameters, held for the whole fit.
  std::vector<Block> blocks;
  problem.model(base, &blocks);
  problem.set_blocks(blocks);
  const std::vector<bool> all(params.size(), true);
  std::vector<double> jtj;
  const double chi2 = f.minimise(theta, all, options.iterations, &jtj);
  Result out;
  out.best = f.scene_at(theta);
  const std::vector<ModelRow> m = problem.model(out.best, nullptr);
  const std::vector<double> z = problem.z(m);
  out.chi2 = chi2;
  out.chi2_diagonal = sum_squares(z);
  out.dof = static_cast<int>(data.size()) - static_cast<int>(params.size());
  for (std::size_t i = 0; i < data.size(); ++i) out.residuals.push_back({data[i], m[i], z[i]});
  // Curvature: cov = (J^T J)^-1, scaled by chi2/dof when above 1.
  const std::size_t p = params.size();
  std::vector<double> cov = invert(jtj, p);
  const double scale = std::max(1.0, chi2 / std::max(1, out.dof));
  for (double& c : cov) c *= scale;
  for (std::size_t k = 0; k < p; ++k) {
    const double s = std::sqrt(std::max(0.0, cov[k * p + k]));
    out.parameters.push_back({params[k].name, std::exp(start[k]), std::exp(theta[k]), std::exp(theta[k] - 1.96 * s),
                              std::exp(theta[k] + 1.96 * s), "curvature"});
  }
  if (options.profile) {
    for (std::size_t k = 0; k < p; ++k) {
      const double s = std::max(0.02, std::sqrt(std::max(0.0, cov[k * p + k])));
      std::vector<bool> free(p, true);
      free[k] = false;
      double bounds[2] = {theta[k], theta[k]};
      for (int side = 0; side < 2; ++side) {
        const double dir = side == 0 ? -1.0 : 1.0;
        double previous_value = theta[k], previous_delta = 0.0;
        bool crossed = false;
        std::vector<double> t = theta;
        for (int j = 1; j <= options.profile_points && !crossed; ++j) {
          t[k] = theta[k] + dir * j * s;
          const double c = f.minimise(t, free, 3, nullptr);
          const double delta = (c - chi2) / scale;
          if (delta >= 3.84) {  // 95 % for one parameter
            const double w = (3.84 - previous_delta) / std::max(1e-12, delta - previous_delta);
            bounds[side] = previous_value + w * (t[k] - previous_value);
            crossed = true;
          } else {
            previous_value = t[k];
            previous_delta = std::max(0.0, delta);
            bounds[side] = t[k];
          }
        }
      }
      out.parameters[k].lo = std::exp(bounds[0]);
      out.parameters[k].hi = std::exp(bounds[1]);
      out.parameters[k].method = "profile";
    }
  }
  // Predictions: the best fit with every seed, and parameter sets drawn from N(theta, cov)
  // (one seed each) for the parameters' share of the uncertainty.
  if (!options.predict_days.empty()) {
    const std::vector<double> l = [&] {
      std::vector<double> a = cov;
      for (std::size_t k = 0; k < p; ++k) a[k * p + k] += 1e-12;
      return cholesky(a, p);
    }();
    std::map<std::pair<int, double>, std::vector<double>> draws;
    std::map<std::pair<int, double>, std::pair<double, double>> best;
    for (const double age : options.predict_days) {
      for (const morphology::Row& r : morphology::population(grow(at_age(out.best, age), options.seeds))) {
        const int k = statistic_index(r.statistic);
        best[{k, age}] = {r.mean, r.se};
      }
    }
    for (int d = 0; d < options.predict_draws; ++d) {
      core::Rng rng(base.seed, core::Stream::kValidation, static_cast<std::uint64_t>(d), 41);
      std::vector<double> e(p), t = theta;
      for (double& x : e) x = core::normal(rng);
      for (std::size_t a = 0; a < p; ++a)
        for (std::size_t b = 0; b <= a; ++b) t[a] += l[a * p + b] * e[b];
      const Scene s = f.scene_at(f.clamp(t));
      try {  // a drawn set whose arbours would not fit in memory is counted and left out
        std::map<std::pair<int, double>, double> one;
        for (const double age : options.predict_days)
          for (const morphology::Row& r : morphology::population(grow(at_age(s, age), {options.seeds.front()})))
            one[{statistic_index(r.statistic), age}] = r.mean;
        for (const auto& [key, mean] : one) draws[key].push_back(mean);
      } catch (const RunError&) {
        ++out.refused_draws;
      }
    }
    for (const double age : options.predict_days)
      for (std::size_t k = 0; k < morphology::statistic_names().size(); ++k) {
        // The 2.5 and 97.5 percentiles of the drawn parameter sets' means (the draws also
        // carry one seed's sampling noise), around the best fit's mean over every seed.
        std::vector<double> v = draws[{static_cast<int>(k), age}];
        std::sort(v.begin(), v.end());
        if (v.empty()) v.push_back(std::nan(""));
        const auto at = [&](double q) {
          const double x = q * static_cast<double>(v.size() - 1);
          const std::size_t i = static_cast<std::size_t>(x);
          return i + 1 < v.size() ? v[i] + (x - static_cast<double>(i)) * (v[i + 1] - v[i]) : v.back();
        };
        const double bm = best[{static_cast<int>(k), age}].first;
        out.predictions.push_back({morphology::statistic_names()[k], age, bm, at(0.025), at(0.975)});
      }
  }
  out.evaluations = problem.evaluations();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

std::vector<ModelRow> model_at(const Scene& base, double age_days, const std::vector<std::uint64_t>& seeds) {
  std::vector<ModelRow> out;
  for (const morphology::Row& r : morphology::population(grow(at_age(base, age_days), seeds)))
    out.push_back({r.statistic, age_days, static_cast<double>(r.n), r.mean, r.se});
  return out;
}

void write_result(const Result& r, const std::string& dir) {
  fs::create_directories(dir);
  json j;
  j["chi2"] = r.chi2;
  j["dof"] = r.dof;
  j["chi2_per_dof"] = r.chi2 / std::max(1, r.dof);
  j["chi2_ignoring_correlations"] = r.chi2_diagonal;
  j["correlations"] = fmt::format(
      "chi2 = sum over ages of z^T R^-1 z in two blocks (the six per-neuron statistics; the five per-dendrite ones), "
      "R the correlation of those statistics over the model's neurons (dendrites) at the starting parameters, shrunk "
      "{:.0f} % toward the identity; z = (model - data) / sqrt(se_data^2 + se_model^2)",
      kShrink * 100);
  j["evaluations"] = r.evaluations;
  j["prediction_draws_refused"] = r.refused_draws;
  j["seconds"] = r.seconds;
  json ps = json::array();
  for (const Interval& p : r.parameters)
    ps.push_back({{"name", p.name}, {"start", p.start}, {"best", p.best}, {"lo95", p.lo}, {"hi95", p.hi},
                  {"interval", p.method}});
  j["parameters"] = ps;
  std::ofstream(fs::path(dir) / "fit.json") << j.dump(2) << "\n";
  std::ofstream res(fs::path(dir) / "residuals.csv");
  res << "statistic,age_days,data_mean,data_se,model_mean,model_se,z\n";
  for (const Residual& x : r.residuals)
    res << fmt::format("{},{},{},{},{},{},{}\n", x.data.statistic, x.data.age_days, x.data.mean, x.data.se, x.model.mean,
                       x.model.se, x.z);
  std::ofstream pr(fs::path(dir) / "predictions.csv");
  pr << "statistic,age_days,mean,lo95,hi95\n";
  for (const Prediction& x : r.predictions)
    pr << fmt::format("{},{},{},{},{}\n", x.statistic, x.age_days, x.mean, x.lo, x.hi);
  std::ofstream(fs::path(dir) / "scene.json") << scene_to_json(r.best).dump(2) << "\n";
}

}  // namespace axg::morphofit
