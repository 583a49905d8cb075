// axonguide._core: sweeps, assay metrics and the fit (docs/methods.md §12, docs/guide.md §2).
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <tuple>

#include <fmt/format.h>

#include "axonguide/study/assay.hpp"
#include "axonguide/study/fit.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/study/sweep.hpp"
#include "axonguide/support/threads.hpp"
#include "common.hpp"

namespace axg::py_api {

namespace {

using nlohmann::json;

struct SpecHandle {
  sweep::Spec spec;
  std::string origin;
};

SpecHandle spec_from_file(const std::string& path) { return {sweep::load_spec(path), path}; }

// As load_spec, from the text of a sweep file whose relative scene paths start at `folder`.
SpecHandle spec_from_text(const std::string& text, const std::string& origin, const std::string& folder) {
  try {
    const json j = parse_json_strict(text, fmt::format("sweep {}", origin));
    return {sweep::parse_spec(j, origin, folder), origin};
  } catch (const InputError& e) {
    throw InputError(printable(e.what()));
  }
}

template <class T>
py::array_t<T> to_array(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// Columns of sweep.csv (records) and summary.csv (summary), from the members in order.
py::dict sweep_tables(const sweep::Spec& spec, const std::vector<sweep::MemberResult>& members) {
  const auto& names = assay::scalar_metric_names();
  const std::size_t total = members.size(), S = spec.seeds.size(), P = sweep::point_count(spec);
  std::vector<std::vector<json>> point_values(P);
  for (std::size_t p = 0; p < P; ++p) point_values[p] = sweep::point_values(spec, p);

  py::dict rec;
  std::vector<std::uint64_t> member(total), point(total), seed(total);
  std::vector<std::int32_t> exit_code(total);
  std::vector<bool> reused(total);
  py::list status, sha, message;
  std::vector<std::vector<double>> metric(names.size(), std::vector<double>(total));
  for (std::size_t m = 0; m < total; ++m) {
    const sweep::MemberResult& r = members[m];
    member[m] = m;
    point[m] = m / S;
    seed[m] = spec.seeds[m % S];
    exit_code[m] = r.exit_code;
    reused[m] = r.skipped;
    status.append(r.ok ? "ok" : "failed");
    sha.append(r.connections_sha256);
    message.append(r.message);
    for (std::size_t k = 0; k < names.size(); ++k) metric[k][m] = r.metrics[k].second;
  }
  rec["member"] = to_array(member);
  rec["point"] = to_array(point);
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    py::list col;
    for (std::size_t m = 0; m < total; ++m) col.append(json_to_py(point_values[m / S][k]));
    rec[py::str(spec.parameters[k].name)] = col;
  }
  rec["seed"] = to_array(seed);
  rec["status"] = status;
  rec["exit_code"] = to_array(exit_code);
  for (std::size_t k = 0; k < names.size(); ++k) rec[py::str(names[k])] = to_array(metric[k]);
  rec["connections_sha256"] = sha;
  rec["message"] = message;
  py::array_t<bool> re(static_cast<py::ssize_t>(total));
  for (std::size_t m = 0; m < total; ++m) re.mutable_data()[m] = reused[m];
  rec["reused"] = re;

  py::dict sum;
  std::vector<std::uint64_t> pts(P), ok(P), failed(P), count(P, S);
  std::vector<std::vector<double>> mean(names.size(), std::vector<double>(P)), lo = mean, hi = mean;
  for (std::size_t p = 0; p < P; ++p) {
    pts[p] = p;
    for (std::size_t s = 0; s < S; ++s) ok[p] += members[p * S + s].ok;
    failed[p] = S - ok[p];
    for (std::size_t k = 0; k < names.size(); ++k) {
      std::vector<double> xs;
      for (std::size_t s = 0; s < S; ++s)
        if (members[p * S + s].ok) xs.push_back(members[p * S + s].metrics[k].second);
      const sweep::MeanCi c = sweep::mean_ci(xs);
      mean[k][p] = c.mean;
      lo[k][p] = c.low;
      hi[k][p] = c.high;
    }
  }
  sum["point"] = to_array(pts);
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    py::list col;
    for (std::size_t p = 0; p < P; ++p) col.append(json_to_py(point_values[p][k]));
    sum[py::str(spec.parameters[k].name)] = col;
  }
  sum["members"] = to_array(count);
  sum["ok"] = to_array(ok);
  sum["failed"] = to_array(failed);
  for (std::size_t k = 0; k < names.size(); ++k) {
    sum[py::str(names[k] + "_mean")] = to_array(mean[k]);
    sum[py::str(names[k] + "_ci_low")] = to_array(lo[k]);
    sum[py::str(names[k] + "_ci_high")] = to_array(hi[k]);
  }
  py::dict out;
  out["records"] = rec;
  out["summary"] = sum;
  return out;
}

py::dict sweep_run(const SpecHandle& h, std::optional<std::string> out, int threads, const std::string& backend) {
  sweep::Options options;
  options.threads = checked_threads(threads);
  options.run = run_options(backend);
  options.backend = backend;
  std::vector<sweep::MemberResult> members;
  std::size_t failed = 0, skipped = 0;
  std::atomic<bool> stop{false};
  options.run.stop_requested = [&stop] { return stop.load(); };
  interruptible(stop, [&] {
    if (out) {
      sweep::Outcome o = sweep::run(h.spec, *out, options);  // the records written are kept: a re-run reuses them
      members = std::move(o.members);
      failed = o.failed;
      skipped = o.skipped;
    } else {
      members = sweep::run_in_memory({h.spec}, options.threads, options.run);
      for (const auto& r : members) failed += !r.ok;
    }
  });
  py::dict d = sweep_tables(h.spec, members);
  d["failed"] = failed;
  d["reused"] = skipped;
  d["threads"] = options.threads;
  return d;
}

py::dict metrics_dict(const assay::Metrics& m) {
  py::dict d;
  for (const auto& [name, value] : assay::scalar_metrics(m)) d[py::str(name)] = value;
  d["axons"] = m.axons;
  d["crossing_axons"] = m.crossing_axons;
  py::array_t<double> theta(assay::kAngleBins), profile(assay::kAngleBins);
  py::array_t<std::uint64_t> profile_axons(assay::kAngleBins), turning(assay::kTurningBins);
  py::array_t<double> edges(assay::kTurningBins + 1);
  for (int j = 0; j < assay::kAngleBins; ++j) {
    theta.mutable_data()[j] = (j + 0.5) * 360.0 / assay::kAngleBins;
    profile.mutable_data()[j] = m.profile[j];
    profile_axons.mutable_data()[j] = m.profile_axons[j];
  }
  for (int k = 0; k < assay::kTurningBins; ++k) turning.mutable_data()[k] = m.turning[k];
  for (int k = 0; k <= assay::kTurningBins; ++k) edges.mutable_data()[k] = -180 + k * 360 / assay::kTurningBins;
  d["profile_theta_deg"] = theta;
  d["profile"] = profile;
  d["profile_axons"] = profile_axons;
  d["turning_edges_deg"] = edges;
  d["turning"] = turning;
  return d;
}

py::dict assay_metrics(const RunHandle& h) {
  const RunResult& r = h.result;
  assay::Metrics m;
  {
    py::gil_scoped_release release;
    m = assay::measure(r.scene, r.soma, r.neurons, assay::reference_cues(r.scene));
  }
  return metrics_dict(m);
}

py::dict fit_run(const std::string& base_text, const std::string& origin, const std::string& data_text,
                 const std::string& data_origin, int threads, const std::vector<std::uint64_t>& seeds, bool scale,
                 double gain_lo, double gain_hi, double kd_lo, double kd_hi, int grid, int refine,
                 const std::string& backend, bool mirror, double target_se, std::size_t max_seeds,
                 const std::vector<std::tuple<std::string, double, double>>& params,
                 const std::vector<std::pair<double, double>>& corrections, const std::string& bias_metric,
                 int polish, bool antithetic) {
  // The options' limits are checked by fit::fit, for the command line and for this alike.
  scene_from_text(base_text, origin);  // SceneError for a bad base scene
  const json base = parse_json_strict(base_text, origin);
  const fit::Data data = fit::parse_data(data_text, data_origin);
  fit::Options o;
  o.threads = checked_threads(threads);
  o.seeds = seeds;
  o.fit_scale = scale;
  o.gain_lo = gain_lo;
  o.gain_hi = gain_hi;
  o.kd_lo = kd_lo;
  o.kd_hi = kd_hi;
  o.coarse = grid;
  o.refine_rounds = refine;
  o.mirror = mirror;
  o.antithetic = antithetic;
  o.target_se_ratio = target_se;
  o.max_seeds = max_seeds;
  o.polish_iterations = polish;
  for (const auto& [name, lo, hi] : params) o.parameters.push_back({name, lo, hi});
  o.corrections = corrections;
  o.bias_metric = bias_metric;
  o.run = run_options(backend);
  std::atomic<bool> stop{false};
  o.run.stop_requested = [&stop] { return stop.load(); };
  const fit::Result r = interruptible(stop, [&] { return fit::fit(base, origin, data, o); });
  const Scene scene = parse_scene(base_text, origin).scene;
  auto value_of = [&](const char* name, double otherwise) {
    for (std::size_t k = 0; k < r.parameters.size(); ++k)
      if (r.parameters[k].name == name) return r.best[k];
    return otherwise;
  };
  py::dict d;
  d["gain"] = value_of("gain", scene.guidance.gain);
  d["kd"] = value_of("kd", scene.cues.sources.empty() ? 0.0 : scene.cues.sources[0].kd);
  d["scale"] = value_of("scale", 1.0);
  py::dict best, intervals;
  std::vector<std::string> names;
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    names.push_back(r.parameters[k].name);
    best[py::str(r.parameters[k].name)] = r.best[k];
    intervals[py::str(r.parameters[k].name)] = py::make_tuple(r.intervals[k].lo, r.intervals[k].hi,
                                                             r.intervals[k].open_low, r.intervals[k].open_high);
  }
  d["parameters"] = names;
  d["best"] = best;
  d["intervals"] = intervals;
  d["chi2"] = r.chi2;
  d["dof"] = r.dof;
  d["chi2_per_dof"] = r.chi2_per_dof;
  d["runs"] = r.runs;
  d["polished"] = r.polished;
  d["seeds"] = r.seeds;
  d["model_se_ratio_max"] = r.se_ratio_max;
  d["bias_metric"] = r.bias_metric;
  d["model"] = to_array(r.model);
  d["model_se"] = to_array(r.model_se);
  d["model_min"] = to_array(r.model_min);
  d["model_max"] = to_array(r.model_max);
  py::array_t<bool> reach(static_cast<py::ssize_t>(r.reachable.size()));
  for (std::size_t i = 0; i < r.reachable.size(); ++i) reach.mutable_data()[i] = r.reachable[i];
  d["reachable"] = reach;
  std::vector<std::string> measure;
  std::vector<std::uint64_t> point;
  for (const auto& q : r.residuals) measure.push_back(fit::measure_name(q.measure)), point.push_back(q.point);
  d["measure"] = measure;
  d["point"] = to_array(point);
  const std::size_t E = r.evaluations.size(), N = r.residuals.size();
  std::vector<double> c(E);
  py::array_t<double> em({static_cast<py::ssize_t>(E), static_cast<py::ssize_t>(N)}),
      es({static_cast<py::ssize_t>(E), static_cast<py::ssize_t>(N)});
  py::dict ev;
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    std::vector<double> v(E);
    for (std::size_t e = 0; e < E; ++e) v[e] = r.evaluations[e].p[k];
    ev[py::str(r.parameters[k].name)] = to_array(v);
  }
  for (std::size_t e = 0; e < E; ++e) {
    const auto& x = r.evaluations[e];
    c[e] = x.chi2;
    for (std::size_t i = 0; i < N; ++i) {
      em.mutable_data()[e * N + i] = x.model[i];
      es.mutable_data()[e * N + i] = x.model_se[i];
    }
  }
  ev["chi2"] = to_array(c);
  ev["model"] = em;
  ev["model_se"] = es;
  d["evaluations"] = ev;
  const std::size_t P = data.points.size();
  std::vector<double> conc(P), steep(P);
  std::vector<std::uint64_t> count(P), line(P);
  for (std::size_t i = 0; i < P; ++i) {
    conc[i] = data.points[i].concentration, steep[i] = data.points[i].steepness;
    count[i] = data.points[i].count, line[i] = data.points[i].line;
  }
  py::dict dd;
  dd["concentration"] = to_array(conc);
  dd["steepness"] = to_array(steep);
  for (int m = 0; m < fit::kMeasures; ++m) {
    if (!data.measured[m]) continue;
    std::vector<double> v(P), se(P);
    for (std::size_t i = 0; i < P; ++i) v[i] = data.points[i].value[m], se[i] = data.points[i].se[m];
    dd[fit::measure_name(m)] = to_array(v);
    dd[data.measure_count() == 1 ? "se" : (std::string(fit::measure_name(m)) + "_se").c_str()] = to_array(se);
  }
  dd["count"] = to_array(count);
  dd["line"] = to_array(line);
  d["data"] = dd;
  return d;
}

}  // namespace

void bind_study(py::module_& m) {
  py::class_<SpecHandle, std::shared_ptr<SpecHandle>>(m, "SweepSpecHandle")
      .def_readonly("origin", &SpecHandle::origin)
      .def_property_readonly("member_count", [](const SpecHandle& h) { return sweep::member_count(h.spec); })
      .def_property_readonly("point_count", [](const SpecHandle& h) { return sweep::point_count(h.spec); })
      .def_property_readonly("seeds", [](const SpecHandle& h) { return h.spec.seeds; })
      .def_property_readonly("write_runs", [](const SpecHandle& h) { return h.spec.write_runs; })
      .def_property_readonly("parameter_names",
                             [](const SpecHandle& h) {
                               std::vector<std::string> names;
                               for (const auto& p : h.spec.parameters) names.push_back(p.name);
                               return names;
                             })
      .def("point_values",
           [](const SpecHandle& h, std::size_t p) {
             if (p >= sweep::point_count(h.spec)) throw py::index_error("point out of range");
             py::list l;
             for (const auto& v : sweep::point_values(h.spec, p)) l.append(json_to_py(v));
             return l;
           })
      .def("member_scene_json",
           [](const SpecHandle& h, std::size_t member) {
             if (member >= sweep::member_count(h.spec)) throw py::index_error("member out of range");
             return sweep::member_scene_json(h.spec, member).dump();
           });
  m.def("sweep_spec_from_file", &spec_from_file, py::arg("path"));
  m.def("sweep_spec_from_text", &spec_from_text, py::arg("text"), py::arg("origin"), py::arg("folder"));
  m.def("sweep", &sweep_run, py::arg("spec"), py::arg("out"), py::arg("threads"), py::arg("backend"));
  m.def("assay_metrics", &assay_metrics, py::arg("run"));
  m.def("metric_names", [] { return assay::scalar_metric_names(); });
  m.def("fit", &fit_run, py::arg("base_text"), py::arg("origin"), py::arg("data_text"), py::arg("data_origin"),
        py::arg("threads"), py::arg("seeds"), py::arg("scale"), py::arg("gain_min"), py::arg("gain_max"),
        py::arg("kd_min"), py::arg("kd_max"), py::arg("grid"), py::arg("refine"), py::arg("backend"),
        py::arg("mirror"), py::arg("target_se"), py::arg("max_seeds"), py::arg("params"), py::arg("corrections"),
        py::arg("bias_metric"), py::arg("polish"), py::arg("antithetic"));
}

}  // namespace axg::py_api
