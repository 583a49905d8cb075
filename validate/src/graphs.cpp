// `validate bfs`: our BFS and components against Boost.Graph on random graphs and on
// simulated networks. `validate gpu`: reference against cuda, byte for byte, on a scene set.
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/breadth_first_search.hpp>
#include <boost/graph/connected_components.hpp>

#include <unistd.h>

#include <map>

#include <fmt/format.h>

#include "axonguide/accel/engines.hpp"
#include "axonguide/core/random.hpp"
#include "axonguide/graph/graph.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/validate.hpp"

namespace axg::validate {

namespace {

namespace fs = std::filesystem;


struct Comparison {
  std::size_t level_mismatch = 0, parent_violations = 0, component_mismatch = 0, reached = 0;
};

Comparison compare_with_boost(const Csr& g, const std::vector<std::uint32_t>& sources) {
  Comparison c;
  const std::size_t n = g.vertices();
  const Csr in = transpose(g);
  const BfsResult ours = bfs(g, in, sources);
  using G = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS>;
  G bg(n);
  for (std::size_t u = 0; u < n; ++u)
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) boost::add_edge(u, g.targets[k], bg);
  std::vector<int> level(n, -1);
  for (std::uint32_t s : sources) level[s] = 0;
  std::vector<boost::default_color_type> color(n);
  boost::queue<G::vertex_descriptor> q;
  boost::breadth_first_search(bg, sources.begin(), sources.end(), q,
                              boost::make_bfs_visitor(boost::record_distances(level.data(), boost::on_tree_edge())),
                              boost::make_iterator_property_map(color.begin(), get(boost::vertex_index, bg)));
  for (std::size_t v = 0; v < n; ++v) {
    c.level_mismatch += ours.level[v] != level[v];
    // Parent rule: the lowest in-neighbour one level up (none for sources and unreached).
    std::uint32_t expect = kNoParent;
    if (ours.level[v] > 0)
      for (std::uint32_t k = in.offsets[v]; k < in.offsets[v + 1]; ++k)
        if (ours.level[in.targets[k]] == ours.level[v] - 1) expect = std::min(expect, in.targets[k]);
    c.parent_violations += ours.parent[v] != expect;
  }
  c.reached = ours.reached;
  boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS> ug(n);
  for (std::size_t u = 0; u < n; ++u)
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) boost::add_edge(u, g.targets[k], ug);
  std::vector<int> bc(n);
  boost::connected_components(ug, bc.data());
  const std::vector<std::uint32_t> comp = components(undirected(g));
  std::map<int, std::uint32_t> lowest;
  for (std::size_t v = 0; v < n; ++v)
    if (!lowest.count(bc[v])) lowest[bc[v]] = static_cast<std::uint32_t>(v);
  for (std::size_t v = 0; v < n; ++v) c.component_mismatch += comp[v] != lowest[bc[v]];
  return c;
}

}  // namespace

void validate_bfs(const Options& o, Report& r) {
  r.text("Levels must equal Boost.Graph's breadth_first_search; parents must be the lowest in-neighbour one "
         "level up; components must be Boost's connected_components partition labelled by lowest id.");
  std::vector<std::vector<std::string>> rows;
  auto record = [&](const std::string& name, const Csr& g, const std::vector<std::uint32_t>& sources) {
    const Comparison c = with_threads(o.threads, [&] { return compare_with_boost(g, sources); });
    rows.push_back({name, std::to_string(g.vertices()), std::to_string(g.edges()), std::to_string(c.reached),
                    std::to_string(c.level_mismatch), std::to_string(c.parent_violations),
                    std::to_string(c.component_mismatch)});
    const bool ok = c.level_mismatch == 0 && c.parent_violations == 0 && c.component_mismatch == 0;
    r.check({"BFS and components equal Boost: " + name, ok,
             fmt::format("{} level, {} parent, {} component mismatches", c.level_mismatch, c.parent_violations,
                         c.component_mismatch),
             "0 mismatches", ""});
  };
  const std::size_t big = o.quick ? 20000 : 300000;
  for (double degree : {0.5, 1.0, 3.0, 8.0}) {
    const std::size_t n = degree > 4 ? big / 4 : big;
    record(fmt::format("random digraph, mean out-degree {}", degree), random_digraph(n, static_cast<std::size_t>(degree * n), 7, core::Stream::kValidation, 300),
           {0, 1, 2});
  }
  record("random digraph, 1 vertex, no edge", random_digraph(1, 0, 1, core::Stream::kValidation, 300), {0});
  for (std::uint64_t seed : {1u, 2u}) {
    Scene s = Scene::builtin_default();
    s.seed = seed;
    s.neurons.count = o.quick ? 3000 : 50000;
    s.neurons.radius = 2.5 * std::cbrt(s.neurons.count / 100.0);
    RunResult res = with_threads(o.threads, [&] { return run_scene(s, RunOptions{}); });
    std::vector<char> has_in(res.neurons.size(), 0);
    for (std::uint32_t t : res.graph.out.targets) has_in[t] = 1;
    std::vector<std::uint32_t> roots;
    for (std::uint32_t v = 0; v < has_in.size(); ++v)
      if (!has_in[v]) roots.push_back(v);
    record(fmt::format("simulated network, {} neurons, seed {}, from all roots", s.neurons.count, seed), res.graph.out, roots);
  }
  r.table({"graph", "vertices", "edges", "reached", "level mismatches", "parent violations", "component mismatches"}, rows,
          "bfs.csv");
}

void validate_gpu(const Options& o, Report& r) {
  if (const std::string why = accel::cuda_unavailable_reason(); !why.empty()) {
    r.skip("reference vs cuda, byte for byte", why);
    return;
  }
  r.text("Device: " + accel::cuda_device_description());
  std::vector<std::vector<std::string>> rows;
  const ScratchDir scratch("axonguide-validate-gpu");
  const fs::path& tmp = scratch.path();
  std::vector<std::pair<std::string, Scene>> scenes{{"builtin-default", Scene::builtin_default()}};
  for (const char* dir : {"scenes"}) {
    const fs::path root = data_dir() / dir;
    if (!fs::exists(root)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(root))
      if (e.path().extension() == ".json" && e.path().string().find(".sweep.json") == std::string::npos)
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) scenes.emplace_back(f.filename().string(), load_scene_file(f.string()).scene);
  }
  if (o.quick) scenes.resize(std::min<std::size_t>(scenes.size(), 3));
  for (const auto& [name, scene] : scenes) {
    std::map<std::string, std::string> hashes[2];
    for (int b = 0; b < 2; ++b) {
      RunOptions opt;
      if (b == 1) opt.make_engine = [](const Scene& s, const Placement& p) { return accel::make_cuda_engine(s, p); };
      const RunResult res = with_threads(o.threads, [&] { return run_scene(scene, opt); });
      const fs::path out = tmp / (name + (b ? ".cuda" : ".ref"));
      const OutputInfo info = write_outputs(res, out, b ? "cuda" : "reference", 0, {});
      for (const auto& [f, h] : info.files)
        if (f != "timings.csv") hashes[b][f] = h;
    }
    const bool same = hashes[0] == hashes[1];
    rows.push_back({name, same ? "identical" : "DIFFERENT"});
    r.check({"reference == cuda, byte for byte: " + name, same, same ? "all files identical" : "files differ",
             "identical SHA-256 of every output except timings", ""});
  }
  r.table({"scene", "outputs"}, rows, "gpu.csv");
}

}  // namespace axg::validate
