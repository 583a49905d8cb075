// The files of SPEC §4. Numbers are printed in their shortest round-trip form, so a
// file's bytes are a function of the values alone.
#include <fmt/format.h>

#include <chrono>
#include <ctime>

#include "axonguide/error.hpp"
#include "axonguide/output.hpp"
#include "axonguide/run.hpp"
#include "axonguide/version.hpp"

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

std::int64_t signed_id(std::uint32_t id) { return id == core::kNoNeuron ? -1 : static_cast<std::int64_t>(id); }

void write_neurons(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("id,soma_x,soma_y,soma_z,radius,status,tip_x,tip_y,tip_z,length,steps,target\n");
  const auto& n = r.neurons;
  const double radius = r.scene.neurons.soma_radius;
  for (std::size_t i = 0; i < n.size(); ++i)
    w.row("{},{},{},{},{},{},{},{},{},{},{},{}\n", i, r.soma[i].x, r.soma[i].y, r.soma[i].z, radius,
          name_of(n.status[i]), n.tip[i].x, n.tip[i].y, n.tip[i].z, n.length[i], n.steps[i],
          signed_id(n.target[i]));
  w.flush();
}

void write_connections(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("source,target,step,length\n");
  const auto& n = r.neurons;
  for (std::size_t i = 0; i < n.size(); ++i)
    if (n.target[i] != core::kNoNeuron) w.row("{},{},{},{}\n", i, n.target[i], n.steps[i], n.length[i]);
  w.flush();
}

void write_stats(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("step,growing,connected,exited,particles\n");
  const std::uint32_t every = r.scene.output.stats_every;
  for (std::size_t k = 0; k < r.stats.size(); ++k) {
    const StepStats& s = r.stats[k];
    if (s.step % every != 0 && k + 1 != r.stats.size()) continue;
    w.row("{},{},{},{},{}\n", s.step, s.growing, s.connected, s.exited, s.particles);
  }
  w.flush();
}

void write_bfs(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  const auto& g = r.graph;
  const bool has_bfs = g.bfs.has_value(), has_comp = !g.component.empty();
  w.row("id{}{}\n", has_bfs ? ",level,parent" : "", has_comp ? ",component" : "");
  for (std::size_t v = 0; v < r.neurons.size(); ++v) {
    w.row("{}", v);
    if (has_bfs) w.row(",{},{}", g.bfs->level[v], g.bfs->parent[v]);
    if (has_comp) w.row(",{}", g.component[v]);
    w.row("\n");
  }
  w.flush();
}

void write_paths(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("id,step,x,y,z\n");
  const auto& n = r.neurons;
  for (std::size_t i = 0; i < n.size(); ++i)
    for (std::size_t s = 0; s < r.paths.size() && s <= n.steps[i]; ++s) {
      const core::Vec3 p = r.paths[s][i];
      w.row("{},{},{},{},{}\n", i, s, p.x, p.y, p.z);
    }
  w.flush();
}

void write_timings(const RunResult& r, AtomicFile& f) {
  CsvWriter w(f);
  w.row("step,phase,seconds\n");
  for (const auto& row : r.times.rows()) w.row("{},{},{:.9f}\n", row.step, row.phase, row.seconds);
  w.flush();
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace

OutputInfo write_outputs(const RunResult& r, const fs::path& dir, const std::string& backend_name,
                         int threads, const std::vector<std::string>& warnings) {
  prepare_output_dir(dir);
  OutputInfo info;
  auto emit = [&](const std::string& name, auto&& writer) {
    AtomicFile f(dir, name);
    writer(r, f);
    f.commit();
    info.files.emplace_back(name, sha256_file(dir / name));
  };
  PhaseTimes output_time;
  const auto t0 = std::chrono::steady_clock::now();
  emit("neurons.csv", write_neurons);
  emit("connections.csv", write_connections);
  emit("stats.csv", write_stats);
  if (r.graph.bfs || !r.graph.component.empty()) emit("bfs.csv", write_bfs);
  if (r.scene.output.paths) emit("paths.csv", write_paths);
  emit("graph.graphml", write_graphml);
  const double output_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  emit("timings.csv", write_timings);

  json manifest;
  manifest["axonguide"] = {{"version", kVersion}, {"commit", kCommit}, {"build_type", kBuildType},
                           {"compiler", kCompiler}, {"cxx_flags", kCxxFlags}};
  manifest["scene"] = scene_to_json(r.scene);
  manifest["seed"] = r.scene.seed;
  manifest["backend"] = backend_name;
  manifest["threads"] = threads;
  manifest["created"] = utc_now();
  const StepStats& last = r.stats.back();
  manifest["summary"] = {{"neurons", r.neurons.size()},
                         {"steps_run", r.steps_run},
                         {"connected", last.connected},
                         {"exited", last.exited},
                         {"max_steps", last.growing},
                         {"placement_redraws", r.placement_redraws},
                         {"components", r.graph.component_count}};
  json phases = json::object();
  for (const auto& row : r.times.rows()) {
    double prev = phases.contains(row.phase) ? phases[row.phase].get<double>() : 0.0;
    phases[row.phase] = prev + row.seconds;
  }
  phases["output"] = output_seconds;
  manifest["timings_seconds"] = phases;
  manifest["warnings"] = warnings;
  json files = json::object();
  for (const auto& [name, hash] : info.files) files[name] = {{"sha256", hash}};
  manifest["files"] = files;
  AtomicFile m(dir, "manifest.json");
  m.write(manifest.dump(2));
  m.write("\n");
  m.commit();
  return info;
}

}  // namespace axg
