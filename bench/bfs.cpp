// BFS: ours (level-synchronous, TBB) against Boost.Graph's breadth_first_search on the
// same CSR, on a random graph and on a simulated network; components likewise.
#include <boost/graph/breadth_first_search.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/connected_components.hpp>
#include <boost/graph/visitors.hpp>
#include <fmt/format.h>
#include <tbb/info.h>

#include "axonguide/core/random.hpp"
#include "axonguide/graph/graph.hpp"
#include "axonguide/placement/placement.hpp"
#include "bench.hpp"

namespace axg::bench {

namespace {

using BoostCsr = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, boost::no_property,
                                                    boost::no_property, std::uint32_t, std::uint32_t>;

BoostCsr to_boost(const Csr& g) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(g.edges());
  for (std::size_t u = 0; u < g.vertices(); ++u)
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k)
      edges.emplace_back(static_cast<std::uint32_t>(u), g.targets[k]);
  return BoostCsr(boost::edges_are_sorted, edges.begin(), edges.end(), g.vertices());
}

// Levels and a BFS tree (the same outputs as ours: distances and predecessors).
std::vector<int> boost_levels(const BoostCsr& bg, const std::vector<std::uint32_t>& sources) {
  std::vector<int> level(num_vertices(bg), -1);
  std::vector<std::uint32_t> parent(num_vertices(bg), 0xffffffffu);
  for (std::uint32_t s : sources) level[s] = 0;
  std::vector<boost::default_color_type> color(num_vertices(bg));
  boost::queue<BoostCsr::vertex_descriptor> queue;
  boost::breadth_first_search(
      bg, sources.begin(), sources.end(), queue,
      boost::make_bfs_visitor(std::make_pair(boost::record_distances(level.data(), boost::on_tree_edge()),
                                             boost::record_predecessors(parent.data(), boost::on_tree_edge()))),
      boost::make_iterator_property_map(color.begin(), get(boost::vertex_index, bg)));
  return level;
}


}  // namespace

std::vector<Row> bfs(const Options& o) {
  std::vector<Row> rows;
  auto emit = [&](Row r) {
    if (o.on_row) o.on_row(r);
    rows.push_back(std::move(r));
  };
  const int threads = o.max_threads > 0 ? o.max_threads : static_cast<int>(tbb::info::default_concurrency());
  const std::size_t n = o.quick ? 100000 : 2000000;

  struct Case {
    std::string name;
    Csr g;
    std::vector<std::uint32_t> sources;
  };
  std::vector<Case> cases;
  cases.push_back({fmt::format("random digraph, {} vertices, avg out-degree 8, from vertex 0", n), random_digraph(n, 8 * n, 7, core::Stream::kBenchmark, 1),
                   std::vector<std::uint32_t>{0}});
  {
    const Scene scene = paper_direct_scene(o.quick ? 20000 : 1000000);
    RunResult r = run_scene(scene, RunOptions{});
    // Multi-source: every neuron no axon reaches (in-degree 0) is a root; levels are the
    // distance along axon chains from the nearest root.
    std::vector<char> has_in(r.neurons.size(), 0);
    for (std::uint32_t t : r.graph.out.targets) has_in[t] = 1;
    Case c{fmt::format("simulated network ({} neurons), from all in-degree-0 roots", scene.neurons.count),
           r.graph.out, {}};
    for (std::uint32_t v = 0; v < has_in.size(); ++v)
      if (!has_in[v]) c.sources.push_back(v);
    cases.push_back(std::move(c));
    cases.push_back({fmt::format("simulated network ({} neurons), undirected view", scene.neurons.count),
                     undirected(r.graph.out), std::vector<std::uint32_t>{0}});
  }
  for (const Case& c : cases) {
    const Csr in = transpose(c.g);
    const BoostCsr bg = to_boost(c.g);
    const double edges = static_cast<double>(c.g.edges());
    BfsResult ours;
    std::vector<int> theirs;
    const Paired p = time_paired([&] { theirs = boost_levels(bg, c.sources); },
                                 [&] { ours = axg::bfs(c.g, in, c.sources); }, 7);
    const double t_ours = p.our_seconds, t_boost = p.peer_seconds;
    bool same = true;
    for (std::size_t v = 0; v < c.g.vertices(); ++v) same = same && ours.level[v] == theirs[v];
    if (c.name.find("undirected") == std::string::npos) {
    emit({"bfs", c.name, "boost breadth_first_search (levels + parents)", 1, double(c.g.vertices()), t_boost, edges / t_boost,
          "edges/s", 1.0, "boost", fmt::format("reached {}", ours.reached)});
    emit({"bfs", c.name, "axonguide bfs (levels + parents)", threads, double(c.g.vertices()), t_ours, edges / t_ours,
          "edges/s", p.speedup, "boost", same ? "levels equal Boost's; paired rounds" : "LEVELS DIFFER FROM BOOST"});
    }
    // Components of the undirected view.
    if (c.name.find("undirected") != std::string::npos) {
      std::vector<std::uint32_t> comp;
      std::vector<int> bc(c.g.vertices());
      const Paired pc = time_paired([&] { boost::connected_components(bg, bc.data()); },
                                    [&] { comp = components(c.g); }, 7);
      const double tc = pc.our_seconds, tb = pc.peer_seconds;
      emit({"components", c.name, "boost connected_components", 1, double(c.g.vertices()), tb, edges / tb, "edges/s",
            1.0, "boost", ""});
      emit({"components", c.name, "axonguide components", 1, double(c.g.vertices()), tc, edges / tc, "edges/s",
            pc.speedup, "boost", "paired rounds"});
    }
  }
  return rows;
}


}  // namespace axg::bench
