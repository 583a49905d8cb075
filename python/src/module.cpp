// axonguide._core: scenes, runs and their results (docs/guide.md §2). The pure-Python
// package (python/axonguide/) wraps these in Scene and Result.
#include <Python.h>

#include <chrono>
#include <cstring>
#include <cstdint>
#include <memory>
#include <optional>
#include <system_error>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "axonguide/accel/backend.hpp"
#include "axonguide/accel/engines.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/io/run_folder.hpp"
#include "axonguide/morphology/arbour.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/version.hpp"
#include "common.hpp"

namespace axg::py_api {

namespace {

// The rows of neurons.csv, connections.csv, stats.csv and sources.csv.
struct NeuronRow {
  std::uint32_t id;
  double soma_x, soma_y, soma_z, radius;
  std::uint8_t status;  // core::AxonStatus: STATUS_NAMES[status]
  double tip_x, tip_y, tip_z, length;
  std::uint32_t steps;
  std::int64_t target;  // -1: none
};
struct ConnectionRow {
  std::uint32_t source, target, step;
  double length;
};
// A synapse scene's connections.csv and synapses.csv.
struct SynapticConnectionRow {
  std::uint32_t source, target, synapses, first_step;
};
struct SynapseRow {
  std::uint32_t pre, post, pre_sample, post_sample;
  double x, y, z, distance;
  std::uint32_t contacts, step;
  std::uint8_t realised;
};
struct StatsRow {
  std::uint32_t step;
  std::uint64_t growing, connected, exited, particles;
};
struct SourceRow {
  std::uint32_t cue;
  std::uint8_t kind;  // 0 attractant, 1 repellent: CUE_KIND_NAMES[kind]
  double x, y, z, emission, diffusion, decay, kd, min_concentration, max_concentration;
};

std::int64_t signed_id(std::uint32_t id) { return id == core::kNoNeuron ? -1 : static_cast<std::int64_t>(id); }

py::object none_if_empty(const std::string& s) { return s.empty() ? py::object(py::none()) : py::object(py::str(s)); }

// Raises the axonguide._errors class `name` (message, key, value, allowed).
void raise_python(const char* name, const std::string& message, py::object key = py::none(),
                  py::object value = py::none(), py::object allowed = py::none()) {
  py::object cls = py::module_::import("axonguide._errors").attr(name);
  py::object exc = cls(fs_text(message), key, value, allowed);
  PyErr_SetObject(cls.ptr(), exc.ptr());
}

// Polls Python's signal handlers while a run works (the GIL released): at most every 0.1 s,
// and only when the run was started from the main thread (the only one that receives
// them). A handler's exception (KeyboardInterrupt for SIGINT) ends the run at the end of
// the current step and is raised by run().
struct SignalPoll {
  bool main_thread = false;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  std::optional<py::error_already_set> error;

  bool poll() {
    if (!main_thread) return false;
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(100)) return false;
    last = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() == 0) return false;
    error.emplace();  // fetches (and clears) the handler's exception
    return true;
  }
};

SceneHandle scene_from_file(const std::string& path) {
  try {
    ParseResult p = load_scene_file(path);
    return {std::move(p.scene), std::move(p.warnings), path};
  } catch (const InputError& e) {
    throw SceneInputError(e);
  }
}

std::shared_ptr<RunHandle> run(const SceneHandle& sh, int threads, const std::string& backend,
                               std::optional<std::uint64_t> seed) {
  Scene scene = sh.scene;
  if (seed) scene.seed = *seed;
  // What can refuse the run does so before any work, as `axonguide run` does.
  RunOptions options = run_options(backend);
  const int n = checked_threads(threads);
  check_memory_estimate(estimate_run_bytes(scene), fmt::format("a run of {} neurons", scene.neurons.count));
  auto poll = std::make_shared<SignalPoll>();
  poll->main_thread = on_python_main_thread();
  options.stop_requested = [poll] { return poll->poll(); };
  auto h = std::make_shared<RunHandle>();
  h->warnings = sh.warnings;
  h->backend = backend;
  h->threads = n;
  try {
    py::gil_scoped_release release;
    h->result = with_threads(n, [&] { return run_scene(scene, options); });
  } catch (const Interrupted&) {
    if (poll->error) throw std::move(*poll->error);
    throw;
  }
  return h;
}

py::array_t<NeuronRow> neurons_array(const RunResult& r) {
  const NeuronState& n = r.neurons;
  py::array_t<NeuronRow> a(static_cast<py::ssize_t>(n.size()));
  NeuronRow* out = a.mutable_data();
  const double radius = r.scene.neurons.soma_radius;
  {
    py::gil_scoped_release release;  // 10^6 rows: 0.2 s on one core, most of it first touches of pages
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n.size(), 1 << 14), [&](const tbb::blocked_range<std::size_t>& b) {
      for (std::size_t i = b.begin(); i != b.end(); ++i)
        out[i] = {static_cast<std::uint32_t>(i), r.soma[i].x, r.soma[i].y, r.soma[i].z, radius,
                  static_cast<std::uint8_t>(n.status[i]), n.tip[i].x, n.tip[i].y, n.tip[i].z, n.length[i], n.steps[i],
                  signed_id(n.target[i])};
    });
  }
  return a;
}

py::object connections_array(const RunResult& r) {
  if (r.scene.synapses) {
    const auto& c = r.synapse_connections;
    py::array_t<SynapticConnectionRow> a(static_cast<py::ssize_t>(c.size()));
    SynapticConnectionRow* out = a.mutable_data();
    for (std::size_t k = 0; k < c.size(); ++k) out[k] = {c[k].source, c[k].target, c[k].synapses, c[k].first_step};
    return a;
  }
  const NeuronState& n = r.neurons;
  std::size_t count = 0;
  for (std::size_t i = 0; i < n.size(); ++i) count += n.target[i] != core::kNoNeuron;
  py::array_t<ConnectionRow> a(static_cast<py::ssize_t>(count));
  ConnectionRow* out = a.mutable_data();
  for (std::size_t i = 0, k = 0; i < n.size(); ++i)
    if (n.target[i] != core::kNoNeuron) out[k++] = {static_cast<std::uint32_t>(i), n.target[i], n.steps[i], n.length[i]};
  return a;
}

// synapses.csv's rows (scenes with synapses; None otherwise).
py::object synapses_array(const RunResult& r) {
  if (!r.scene.synapses) return py::none();
  const network::Appositions& s = r.synapses;
  py::array_t<SynapseRow> a(static_cast<py::ssize_t>(s.size()));
  SynapseRow* out = a.mutable_data();
  for (std::size_t k = 0; k < s.size(); ++k) {
    const network::Contact& c = s.at[k];
    out[k] = {c.pre,           c.post,           c.pre_sample, c.post_sample, s.on_dendrite[k].x, s.on_dendrite[k].y,
              s.on_dendrite[k].z, c.distance,       s.contacts[k], c.step,       s.realised[k]};
  }
  return a;
}

// The rows stats.csv prints: every output.stats_every steps and the last (all: every step).
py::array_t<StatsRow> stats_array(const RunResult& r, bool all) {
  std::vector<StatsRow> rows;
  for (std::size_t k = 0; k < r.stats.size(); ++k) {
    if (!all && !stats_row_printed(r, k)) continue;
    const StepStats& s = r.stats[k];
    rows.push_back({s.step, s.growing, s.connected, s.exited, s.particles});
  }
  py::array_t<StatsRow> a(static_cast<py::ssize_t>(rows.size()));
  std::copy(rows.begin(), rows.end(), a.mutable_data());
  return a;
}

py::array_t<SourceRow> sources_array(const RunResult& r) {
  py::array_t<SourceRow> a(static_cast<py::ssize_t>(r.cues.size()));
  SourceRow* out = a.mutable_data();
  for (std::size_t k = 0; k < r.cues.size(); ++k) {
    const auto& c = r.cues[k];
    out[k] = {static_cast<std::uint32_t>(k), static_cast<std::uint8_t>(c.sign > 0 ? 0 : 1), c.position.x, c.position.y,
              c.position.z, c.emission, c.diffusion, c.decay, c.kd, c.min_c, c.max_c};
  }
  return a;
}

// (steps run + 1, neurons, 3): the tips after each step; None without output.paths.
py::object paths_array(const RunResult& r) {
  if (!r.scene.output.paths || r.paths.empty()) return py::none();
  const std::size_t n = r.neurons.size();
  py::array_t<double> a({static_cast<py::ssize_t>(r.paths.size()), static_cast<py::ssize_t>(n), py::ssize_t{3}});
  double* out = a.mutable_data();
  {
    py::gil_scoped_release release;
    tbb::parallel_for(std::size_t{0}, r.paths.size(),
                      [&](std::size_t s) { std::memcpy(out + s * n * 3, r.paths[s].data(), n * sizeof(core::Vec3)); });
  }
  return a;
}

// Neuron i's arbour (arbour scenes; None otherwise): rows in SWC order, row 0 the soma.
// point (k, 3) float64 in the scene's length unit, parent (k,) int64 (the parent's row; -1
// for the soma), type (k,) uint8 (1 soma, 2 axon, 3 dendrite), step (k,) uint32 (the step
// that made the point; 0 for the soma).
py::object arbour_arrays(const RunResult& r, std::size_t i) {
  if (!r.scene.arbours) return py::none();
  if (i >= r.arbours.size()) throw py::index_error(fmt::format("arbour {}: the run has {} neurons", i, r.arbours.size()));
  const std::vector<morphology::ArbourSample> s = morphology::arbour_samples(r.arbours[i]);
  const auto k = static_cast<py::ssize_t>(s.size() + 1);
  py::array_t<double> point({k, py::ssize_t{3}});
  py::array_t<std::int64_t> parent(k);
  py::array_t<std::uint8_t> type(k);
  py::array_t<std::uint32_t> step(k);
  double* p = point.mutable_data();
  std::int64_t* q = parent.mutable_data();
  std::uint8_t* t = type.mutable_data();
  std::uint32_t* st = step.mutable_data();
  p[0] = r.soma[i].x, p[1] = r.soma[i].y, p[2] = r.soma[i].z;
  q[0] = -1, t[0] = 1, st[0] = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    p[3 * (j + 1)] = s[j].pos.x, p[3 * (j + 1) + 1] = s[j].pos.y, p[3 * (j + 1) + 2] = s[j].pos.z;
    q[j + 1] = static_cast<std::int64_t>(s[j].parent) - 1;  // SWC ids from 1, rows from 0
    t[j + 1] = s[j].type;
    st[j + 1] = s[j].step;
  }
  return py::make_tuple(point, parent, type, step);
}

py::list frames_list(py::object self) {
  const RunResult& r = self.cast<RunHandle&>().result;
  py::list out;
  for (const ParticleFrame& fr : r.frames) {
    static_assert(sizeof(core::Vec3) == 3 * sizeof(double));
    auto pos = readonly_view<double>(reinterpret_cast<const double*>(fr.pos.data()),
                                     {static_cast<py::ssize_t>(fr.pos.size()), 3}, self);
    auto cue = readonly_view<std::uint16_t>(fr.cue.data(), {static_cast<py::ssize_t>(fr.cue.size())}, self);
    out.append(py::make_tuple(fr.step, pos, cue, fr.count, fr.stride));
  }
  return out;
}

py::dict bfs_dict(py::object self) {
  const RunResult& r = self.cast<RunHandle&>().result;
  const GraphAnalysis& g = r.graph;
  py::dict d;
  d["sources"] = r.scene.analysis.bfs_sources;
  if (g.bfs) {
    d["level"] = readonly_view<std::int32_t>(g.bfs->level.data(), {static_cast<py::ssize_t>(g.bfs->level.size())}, self);
    py::array_t<std::int64_t> parent(static_cast<py::ssize_t>(g.bfs->parent.size()));
    for (std::size_t v = 0; v < g.bfs->parent.size(); ++v) parent.mutable_data()[v] = signed_id(g.bfs->parent[v]);
    d["parent"] = parent;
    d["max_level"] = g.bfs->max_level;
    d["reached"] = g.bfs->reached;
  } else {
    d["level"] = py::none();
    d["parent"] = py::none();
    d["max_level"] = py::none();
    d["reached"] = py::none();
  }
  if (!g.component.empty())
    d["component"] = readonly_view<std::uint32_t>(g.component.data(), {static_cast<py::ssize_t>(g.component.size())}, self);
  else
    d["component"] = py::none();
  d["component_count"] = g.component_count;
  d["largest_component"] = g.largest_component;
  return d;
}

// manifest.json's "summary", with the graph's counts.
py::dict summary_dict(const RunResult& r) {
  py::dict d = json_to_py(run_summary(r));
  d["edges"] = r.graph.out.edges();
  d["largest_component"] = r.graph.largest_component;
  d["bfs_reached"] = r.graph.bfs ? py::object(py::int_(r.graph.bfs->reached)) : py::object(py::none());
  d["bfs_max_level"] = r.graph.bfs ? py::object(py::int_(r.graph.bfs->max_level)) : py::object(py::none());
  return d;
}

py::dict timings_dict(const RunResult& r) {
  py::dict d;
  for (const auto& row : r.times.rows()) {
    py::str key(row.phase);
    const double prev = d.contains(key) ? d[key].cast<double>() : 0.0;
    d[key] = prev + row.seconds;
  }
  return d;
}

py::dict write_folder(const RunHandle& h, const std::string& dir, bool force) {
  std::vector<std::string> foreign;
  OutputInfo info;
  {
    py::gil_scoped_release release;
    info = with_threads(h.threads, [&] { return write_run_folder(h.result, dir, force, h.backend, h.threads, h.warnings, &foreign); });
  }
  py::dict files;
  for (const auto& [name, hash] : info.files) files[py::str(name)] = hash;
  py::dict d;
  d["files"] = files;
  d["foreign"] = fs_texts(foreign);
  return d;
}

py::dict verify(const std::string& dir) {
  const FolderCheck c = verify_run_folder(dir);
  py::dict d;
  d["whole"] = c.whole;
  d["status"] = fs_text(c.status);
  d["problems"] = fs_texts(c.problems);
  d["notes"] = fs_texts(c.notes);
  return d;
}

}  // namespace

SceneHandle scene_from_text(const std::string& text, const std::string& origin) {
  try {
    ParseResult p = parse_scene(text, origin);
    return {std::move(p.scene), std::move(p.warnings), origin};
  } catch (const InputError& e) {
    throw SceneInputError(e);
  }
}

RunOptions run_options(const std::string& backend) {
  if (backend != "reference" && backend != "cuda" && backend != "emulated")
    throw InputError(fmt::format("backend = \"{}\": must be \"reference\", \"cuda\" or \"emulated\"", printable(backend)));
  RunOptions options;
  options.make_engine = accel::engine_factory(backend);  // RunError when the GPU cannot run
  return options;
}

int checked_threads(int threads) {
  if (threads < 0 || threads > 4096)
    throw InputError(fmt::format("threads = {}: must be None or 0 (all cores) to 4096", threads));
  return resolve_threads(threads);
}

py::object json_to_py(const nlohmann::json& j) {
  using T = nlohmann::json::value_t;
  switch (j.type()) {
    case T::null: return py::none();
    case T::boolean: return py::bool_(j.get<bool>());
    case T::number_integer: return py::int_(j.get<std::int64_t>());
    case T::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case T::number_float: return py::float_(j.get<double>());
    case T::string: return py::str(j.get<std::string>());
    case T::array: {
      py::list l;
      for (const auto& x : j) l.append(json_to_py(x));
      return l;
    }
    case T::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[py::str(it.key())] = json_to_py(it.value());
      return d;
    }
    default: return py::none();
  }
}

}  // namespace axg::py_api

using axg::py_api::ConnectionRow;
using axg::py_api::NeuronRow;
using axg::py_api::SourceRow;
using axg::py_api::StatsRow;
using axg::py_api::SynapseRow;
using axg::py_api::SynapticConnectionRow;

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  using namespace axg;
  using namespace axg::py_api;
  m.doc() = "axonguide's C++ core (use the axonguide package)";
  PYBIND11_NUMPY_DTYPE(NeuronRow, id, soma_x, soma_y, soma_z, radius, status, tip_x, tip_y, tip_z, length, steps, target);
  PYBIND11_NUMPY_DTYPE(ConnectionRow, source, target, step, length);
  PYBIND11_NUMPY_DTYPE(StatsRow, step, growing, connected, exited, particles);
  PYBIND11_NUMPY_DTYPE(SynapticConnectionRow, source, target, synapses, first_step);
  PYBIND11_NUMPY_DTYPE(SynapseRow, pre, post, pre_sample, post_sample, x, y, z, distance, contacts, step, realised);
  PYBIND11_NUMPY_DTYPE(SourceRow, cue, kind, x, y, z, emission, diffusion, decay, kd, min_concentration,
                       max_concentration);

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SceneInputError& e) {
      raise_python("SceneError", e.what(), none_if_empty(e.key()), none_if_empty(e.value()), none_if_empty(e.allowed()));
    } catch (const InputError& e) {
      raise_python("InputError", e.what(), none_if_empty(e.key()), none_if_empty(e.value()), none_if_empty(e.allowed()));
    } catch (const RunError& e) {
      raise_python("RunError", e.what());
    } catch (const Interrupted& e) {
      raise_python("RunError", fmt::format("interrupted after step {}", e.step));
    } catch (const std::system_error& e) {
      // std::filesystem's errors (a name too long, a folder that cannot be read): what the
      // command line reports with exit 3.
      raise_python("RunError", e.what());
    }
  });

  m.attr("__version__") = kVersion;
  m.attr("commit") = kCommit;
  m.attr("STATUS_NAMES") = py::make_tuple(name_of(core::AxonStatus::kGrowing), name_of(core::AxonStatus::kConnected),
                                          name_of(core::AxonStatus::kExited), name_of(core::AxonStatus::kMaxSteps));
  m.attr("CUE_KIND_NAMES") = py::make_tuple("attractant", "repellent");

  py::class_<SceneHandle, std::shared_ptr<SceneHandle>>(m, "SceneHandle")
      .def("canonical_json",
           [](const SceneHandle& s, int indent) {
             // nlohmann's serializer reads past its indent buffer for a wide indent.
             if (indent < -1 || indent > 32)
               throw InputError(fmt::format("indent = {}: must be None or 0 to 32", indent));
             return scene_to_json(s.scene).dump(indent);
           },
           py::arg("indent") = -1)
      .def_readonly("warnings", &SceneHandle::warnings)
      .def_readonly("origin", &SceneHandle::origin)
      .def_property_readonly("seed", [](const SceneHandle& s) { return s.scene.seed; })
      .def("with_seed",
           [](const SceneHandle& s, std::uint64_t seed) {
             SceneHandle c = s;
             c.scene.seed = seed;
             return c;
           })
      .def_property_readonly("neuron_count", [](const SceneHandle& s) { return s.scene.neurons.count; })
      .def_property_readonly("steps", [](const SceneHandle& s) { return s.scene.steps; })
      .def("estimate_bytes", [](const SceneHandle& s) { return estimate_run_bytes(s.scene); })
      .def("planned_outputs", [](const SceneHandle& s) { return planned_outputs(s.scene); });

  m.def("scene_from_text", &scene_from_text, py::arg("text"), py::arg("origin"));
  m.def("scene_from_file", &scene_from_file, py::arg("path"));
  m.def("scene_default", [] { return SceneHandle{Scene::builtin_default(), {}, "built-in default"}; });

  py::class_<RunHandle, std::shared_ptr<RunHandle>>(m, "RunHandle")
      .def("neurons", [](const RunHandle& h) { return neurons_array(h.result); })
      .def("connections", [](const RunHandle& h) { return connections_array(h.result); })
      .def("stats", [](const RunHandle& h, bool all) { return stats_array(h.result, all); }, py::arg("all") = false)
      .def("sources", [](const RunHandle& h) { return sources_array(h.result); })
      .def("paths", [](const RunHandle& h) { return paths_array(h.result); })
      .def("soma",
           [](py::object self) {
             const auto& soma = self.cast<RunHandle&>().result.soma;
             return readonly_view<double>(reinterpret_cast<const double*>(soma.data()),
                                          {static_cast<py::ssize_t>(soma.size()), 3}, self);
           })
      .def("frames", &frames_list)
      .def("arbour", [](const RunHandle& h, std::size_t i) { return arbour_arrays(h.result, i); }, py::arg("i"))
      .def("synapses", [](const RunHandle& h) { return synapses_array(h.result); })
      .def("bfs", &bfs_dict)
      .def("summary", [](const RunHandle& h) { return summary_dict(h.result); })
      .def("timings", [](const RunHandle& h) { return timings_dict(h.result); })
      .def("scene", [](const RunHandle& h) { return SceneHandle{h.result.scene, h.warnings, "run"}; })
      .def("connections_csv", [](const RunHandle& h) { return py::bytes(connections_csv(h.result)); })
      .def("write", &write_folder, py::arg("dir"), py::arg("force") = false)
      .def_readonly("backend", &RunHandle::backend)
      .def_readonly("threads", &RunHandle::threads)
      .def_readonly("warnings", &RunHandle::warnings);

  m.def("run", &axg::py_api::run, py::arg("scene"), py::arg("threads"), py::arg("backend"), py::arg("seed"));
  m.def("verify", &verify, py::arg("dir"));
  m.def("cuda_unavailable_reason", [] { return accel::cuda_unavailable_reason(); });

  bind_study(m);
}
