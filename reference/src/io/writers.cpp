// The files of SPEC §4. Numbers are printed in their shortest round-trip form, so a
// file's bytes are a function of the values alone; every NaN is printed "nan" (canonical()).
#include <fmt/compile.h>
#include <fmt/format.h>

#include <chrono>
#include <ctime>

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "axonguide/io/canonical_nan.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/fault.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/io/run_folder.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/io/sonata.hpp"
#include "axonguide/io/swc.hpp"
#include "axonguide/version.hpp"
#include "axonguide/io/vtk.hpp"

namespace axg {

namespace fs = std::filesystem;
using nlohmann::json;

void write_graphml(const RunResult& r, AtomicFile& file);

namespace {

// Appends to a buffer and hands full chunks to the file.
class CsvWriter {
 public:
  explicit CsvWriter(AtomicFile& f) : f_(f) {}
  template <class... Args>
  void row(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(buf_), format, std::forward<Args>(args)...);
    if (buf_.size() > (1u << 16)) flush();
  }
  void flush() {
    f_.write(std::string_view(buf_.data(), buf_.size()));
    buf_.clear();
  }

 private:
  AtomicFile& f_;
  fmt::memory_buffer buf_;
};

// Formats rows [0, n) in parallel chunks and writes them in order: the bytes are those of
// a sequential loop. row(i, buffer) appends row i. Two batches of chunks alternate: while
// the calling thread writes (and hashes) one batch, the other threads format the next.
template <class Sink, class RowFn>
void write_rows(Sink& f, std::size_t n, RowFn row) {
  constexpr std::size_t kRows = 4096, kBatch = 32;
  std::vector<fmt::memory_buffer> chunks[2] = {std::vector<fmt::memory_buffer>(kBatch),
                                               std::vector<fmt::memory_buffer>(kBatch)};
  auto batch_count = [&](std::size_t first) { return std::min(kBatch, (n - first + kRows - 1) / kRows); };
  auto format = [&](std::size_t first, std::vector<fmt::memory_buffer>& out) {
    tbb::parallel_for(std::size_t{0}, batch_count(first), [&](std::size_t c) {
      out[c].clear();
      const std::size_t begin = first + c * kRows, end = std::min(n, begin + kRows);
      for (std::size_t i = begin; i < end; ++i) row(i, out[c]);
    });
  };
  if (n == 0) return;
  format(0, chunks[0]);
  int cur = 0;
  for (std::size_t first = 0; first < n; first += kRows * kBatch, cur ^= 1) {
    const std::size_t next = first + kRows * kBatch;
    tbb::task_group formatting;
    if (next < n) formatting.run([&, next, cur] { format(next, chunks[cur ^ 1]); });
    for (std::size_t c = 0; c < batch_count(first); ++c)
      f.write(std::string_view(chunks[cur][c].data(), chunks[cur][c].size()));
    formatting.wait();
  }
}

std::int64_t signed_id(std::uint32_t id) { return id == core::kNoNeuron ? -1 : static_cast<std::int64_t>(id); }

void write_neurons(const RunResult& r, AtomicFile& f) {
  f.write("id,soma_x,soma_y,soma_z,radius,status,tip_x,tip_y,tip_z,length,steps,target\n");
  const auto& n = r.neurons;
  const double radius = canonical(r.scene.neurons.soma_radius);
  write_rows(f, n.size(), [&](std::size_t i, fmt::memory_buffer& b) {
    const core::Vec3 soma = canonical(r.soma[i]), tip = canonical(n.tip[i]);
    fmt::format_to(fmt::appender(b), FMT_COMPILE("{},{},{},{},{},{},{},{},{},{},{},{}\n"), i, soma.x, soma.y, soma.z, radius,
                   name_of(n.status[i]), tip.x, tip.y, tip.z, canonical(n.length[i]), n.steps[i],
                   signed_id(n.target[i]));
  });
}

template <class Sink>
void write_connections_to(const RunResult& r, Sink& f) {
  f.write("source,target,step,length\n");
  const auto& n = r.neurons;
  write_rows(f, n.size(), [&](std::size_t i, fmt::memory_buffer& b) {
    if (n.target[i] != core::kNoNeuron)
      fmt::format_to(fmt::appender(b), FMT_COMPILE("{},{},{},{}\n"), i, n.target[i], n.steps[i], canonical(n.length[i]));
  });
}

// A synapse scene: one row per connection with a realised synapse, by source then target.
template <class Sink>
void write_synapse_connections_to(const RunResult& r, Sink& f) {
  f.write("source,target,synapses,first_step\n");
  const auto& c = r.synapse_connections;
  write_rows(f, c.size(), [&](std::size_t k, fmt::memory_buffer& b) {
    fmt::format_to(fmt::appender(b), FMT_COMPILE("{},{},{},{}\n"), c[k].source, c[k].target, c[k].synapses,
                   c[k].first_step);
  });
}

void write_connections(const RunResult& r, AtomicFile& f) {
  if (r.scene.synapses) return write_synapse_connections_to(r, f);
  write_connections_to(r, f);
}

// One row per apposition (SPEC §3.9): the closest contact's samples in morphologies/<pre>.swc
// and morphologies/<post>.swc (a soma: 1), its point on the dendrite, its distance, the run's
// contacts, its first step and whether it is realised as a synapse.
void write_synapses(const RunResult& r, AtomicFile& f) {
  f.write("pre,post,pre_sample,post_sample,x,y,z,distance,contacts,step,realised\n");
  const network::Appositions& a = r.synapses;
  write_rows(f, a.size(), [&](std::size_t k, fmt::memory_buffer& b) {
    const network::Contact& c = a.at[k];
    const core::Vec3 p = canonical(a.on_dendrite[k]);
    fmt::format_to(fmt::appender(b), FMT_COMPILE("{},{},{},{},{},{},{},{},{},{},{}\n"), c.pre, c.post, c.pre_sample,
                   c.post_sample, p.x, p.y, p.z, canonical(c.distance), a.contacts[k], c.step, a.realised[k]);
  });
}

struct StringSink {
  std::string text;
  void write(std::string_view s) { text.append(s); }
};

void write_stats(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("step,growing,connected,exited,particles\n");
  for (std::size_t k = 0; k < r.stats.size(); ++k) {
    if (!stats_row_printed(r, k)) continue;
    const StepStats& s = r.stats[k];
    w.row("{},{},{},{},{}\n", s.step, s.growing, s.connected, s.exited, s.particles);
  }
  w.flush();
}

void write_bfs(const RunResult& r, AtomicFile& f) {
  const auto& g = r.graph;
  const bool has_bfs = g.bfs.has_value(), has_comp = !g.component.empty();
  f.write(fmt::format("id{}{}\n", has_bfs ? ",level,parent" : "", has_comp ? ",component" : ""));
  write_rows(f, r.neurons.size(), [&](std::size_t v, fmt::memory_buffer& b) {
    auto out = fmt::appender(b);
    fmt::format_to(out, FMT_COMPILE("{}"), v);
    if (has_bfs) fmt::format_to(out, FMT_COMPILE(",{},{}"), g.bfs->level[v], signed_id(g.bfs->parent[v]));
    if (has_comp) fmt::format_to(out, FMT_COMPILE(",{}"), g.component[v]);
    b.push_back('\n');
  });
}

// Arbour scenes: every point of every growth cone, neuron by neuron, cone by cone (the SWC
// order: a neuron's k-th row is sample k + 2 of morphologies/<id>.swc), with the cone's
// parent cone (-1 for a stem), its type and order, the step that made it, and the SWC
// sample the point hangs on (1: the soma; a branch point for a cone's first point).
void write_arbour_paths(const RunResult& r, AtomicFile& f) {
  f.write("id,cone,parent,type,order,step,x,y,z,parent_sample\n");
  write_rows(f, r.arbours.size(), [&](std::size_t i, fmt::memory_buffer& b) {
    const morphology::Arbour& a = r.arbours[i];
    for (const morphology::ArbourSample& s : morphology::arbour_samples(a)) {
      const core::Vec3 p = canonical(s.pos);
      const std::uint32_t parent = a.cones[s.cone].parent;
      fmt::format_to(fmt::appender(b), FMT_COMPILE("{},{},{},{},{},{},{},{},{},{}\n"), i, s.cone,
                     parent == morphology::kNoCone ? std::int64_t{-1} : std::int64_t{parent}, s.type, s.order, s.step,
                     p.x, p.y, p.z, s.parent);
    }
  });
}

void write_paths(const RunResult& r, AtomicFile& f) {
  if (r.scene.arbours) return write_arbour_paths(r, f);
  f.write("id,step,x,y,z\n");
  const auto& n = r.neurons;
  write_rows(f, n.size(), [&](std::size_t i, fmt::memory_buffer& b) {
    for (std::size_t s = 0; s < r.paths.size() && s <= n.steps[i]; ++s) {
      const core::Vec3 p = canonical(r.paths[s][i]);
      fmt::format_to(fmt::appender(b), FMT_COMPILE("{},{},{},{},{}\n"), i, s, p.x, p.y, p.z);
    }
  });
}

void write_sources(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("cue,kind,x,y,z,emission,diffusion,decay,kd,min_concentration,max_concentration\n");
  for (std::size_t k = 0; k < r.cues.size(); ++k) {
    const auto& c = r.cues[k];
    const core::Vec3 p = canonical(c.position);
    w.row("{},{},{},{},{},{},{},{},{},{},{}\n", k, c.sign > 0 ? "attractant" : "repellent", p.x, p.y, p.z,
          canonical(c.emission), canonical(c.diffusion), canonical(c.decay), canonical(c.kd), canonical(c.min_c),
          canonical(c.max_c));
  }
  w.flush();
}

void write_particles(const RunResult& r, AtomicFile& f) {
  f.write("step,cue,x,y,z\n");
  for (const ParticleFrame& fr : r.frames)
    write_rows(f, fr.pos.size(), [&](std::size_t i, fmt::memory_buffer& b) {
      const core::Vec3 p = canonical(fr.pos[i]);
      fmt::format_to(fmt::appender(b), FMT_COMPILE("{},{},{},{},{}\n"), fr.step, fr.cue[i], p.x, p.y, p.z);
    });
}

void write_timings(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("step,phase,seconds\n");
  for (const auto& row : r.times.rows()) w.row("{},{},{:.9f}\n", row.step, row.phase, canonical(row.seconds));
  w.flush();
}

}  // namespace

std::vector<std::string> planned_outputs(const Scene& s) {
  std::vector<std::string> names = {"stats.csv", "timings.csv"};
  if (s.output.csv) names.insert(names.begin(), {"neurons.csv", "connections.csv"});
  if (s.output.csv && s.synapses) names.push_back("synapses.csv");
  if (s.writes_graphml()) names.push_back("graph.graphml");
  if (!s.analysis.bfs_sources.empty() || s.analysis.components) names.push_back("bfs.csv");
  if (s.output.paths) names.push_back("paths.csv");
  if (s.uses_cues()) names.push_back("sources.csv");
  if ((s.output.paths || s.output.vtk) && s.uses_cues() && s.cues.field == FieldKind::kParticles)
    names.push_back("particles.csv");
  if (s.output.vtk) {
    names.push_back("growth.pvd");
    names.push_back("vtk/*.vtp");
  }
  if (s.output.swc) names.push_back("morphologies/*.swc");
  if (s.output.sonata)
    for (const char* f : kSonataFiles) names.push_back(f);
  if (s.output.sonata && s.arbours) names.push_back("network/morphologies/*.swc");
  return names;
}

bool stats_row_printed(const RunResult& r, std::size_t k) {
  return r.stats[k].step % r.scene.output.stats_every == 0 || k + 1 == r.stats.size();
}

json run_summary(const RunResult& r) {
  const StepStats& last = r.stats.back();
  json summary = {{"neurons", r.neurons.size()},
          {"steps_run", r.steps_run},
          {"connected", last.connected},
          {"exited", last.exited},
          {"max_steps", last.growing},
          {"placement_redraws", r.placement_redraws},
          {"components", r.graph.component_count},
          {"particles_at_end", last.particles},
          {"cue_field", r.field_note}};
  if (r.scene.synapses) {  // only then: older manifests keep their bytes
    std::size_t realised = 0;
    for (const std::uint8_t x : r.synapses.realised) realised += x;
    summary["contacts"] = r.contacts;
    summary["appositions"] = r.synapses.size();
    summary["synapses"] = realised;
    summary["synaptic_connections"] = r.synapse_connections.size();
  }
  return summary;
}

std::string connections_csv(const RunResult& r) {
  StringSink sink;
  if (r.scene.synapses) write_synapse_connections_to(r, sink);
  else write_connections_to(r, sink);
  return std::move(sink.text);
}

OutputInfo write_outputs(const RunResult& r, const fs::path& dir, const std::string& backend_name,
                         int threads, const std::vector<std::string>& warnings) {
  prepare_output_dir(dir);
  OutputInfo info;
  // The data files are renamed into place with their write-back started but not awaited,
  // so that the kernel writes one while the next is formatted; one sync waits for them all
  // before the manifest names them.
  auto emit = [&](const std::string& name, auto&& writer, AtomicFile::Sync sync = AtomicFile::Sync::kDeferred) {
    AtomicFile f(dir, name, sync);
    writer(r, f);
    info.files.emplace_back(name, f.commit());
  };
  const auto t0 = std::chrono::steady_clock::now();
  if (r.scene.output.csv) {
    emit("neurons.csv", write_neurons);
    emit("connections.csv", write_connections);
    if (r.scene.synapses) emit("synapses.csv", write_synapses);
  }
  emit("stats.csv", write_stats);
  if (r.graph.bfs || !r.graph.component.empty()) emit("bfs.csv", write_bfs);
  if (r.scene.output.paths) emit("paths.csv", write_paths);
  if (!r.cues.empty()) emit("sources.csv", write_sources);
  if (!r.frames.empty()) emit("particles.csv", write_particles);
  if (r.scene.writes_graphml()) emit("graph.graphml", write_graphml);
  if (r.scene.output.vtk) write_vtk(r, dir, info);
  if (r.scene.output.swc) write_swc(r, dir, info);
  if (r.scene.output.sonata) write_sonata(r, dir, info);
  sync_filesystem(dir);
  const double output_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  emit("timings.csv", write_timings, AtomicFile::Sync::kFile);

  json manifest = manifest_header(r.scene, backend_name, threads, {});
  manifest["status"] = "complete";
  manifest["summary"] = run_summary(r);
  if (!r.decomposition.is_null()) manifest["decomposition"] = r.decomposition;
  json phases = json::object();
  for (const auto& row : r.times.rows()) {
    double prev = phases.contains(row.phase) ? phases[row.phase].get<double>() : 0.0;
    phases[row.phase] = prev + row.seconds;
  }
  phases["output"] = output_seconds;
  manifest["timings_seconds"] = phases;
  manifest["peak_memory_bytes"] = peak_rss_bytes();
  std::vector<std::string> all_warnings = warnings;
  for (const ParticleFrame& fr : r.frames)
    if (fr.stride > 1)
      all_warnings.push_back(fmt::format(
          "particle frame at step {} has {} particles: every {}th (by id) kept in particles.csv and the VTK frames",
          fr.step, fr.count, fr.stride));
  manifest["warnings"] = all_warnings;
  json files = json::object();
  for (const auto& [name, hash] : info.files) files[name] = {{"sha256", hash}};
  manifest["files"] = files;
  fault_point("manifest");
  write_manifest(dir, manifest);
  return info;
}

}  // namespace axg
