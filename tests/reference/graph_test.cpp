// Our CSR, BFS (its top-down and bottom-up branches) and components against Boost.Graph on
// random graphs, and the BFS against the accelerator's emulated kernels.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/breadth_first_search.hpp>
#include <boost/graph/connected_components.hpp>

#include <algorithm>
#include <cstdio>
#include <set>

#include "axonguide/accel/engines.hpp"
#include "axonguide/graph/graph.hpp"
#include "axonguide/support/threads.hpp"

namespace axg {
namespace {

struct Edges {
  std::size_t n;
  std::vector<std::uint32_t> src, dst;
};

rc::Gen<Edges> gen_graph() {
  return rc::gen::exec([] {
    Edges e;
    e.n = *rc::gen::inRange<std::size_t>(1, 300);
    const std::size_t m = *rc::gen::inRange<std::size_t>(0, 3 * e.n);
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (std::size_t k = 0; k < m; ++k)
      edges.insert({*rc::gen::inRange<std::uint32_t>(0, static_cast<std::uint32_t>(e.n)),
                    *rc::gen::inRange<std::uint32_t>(0, static_cast<std::uint32_t>(e.n))});
    for (auto [s, t] : edges) e.src.push_back(s), e.dst.push_back(t);
    return e;
  });
}

using BoostGraph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS>;

RC_GTEST_PROP(graph, BfsLevelsEqualBoostAndParentsFollowTheRule, ()) {
  const Edges e = *gen_graph();
  const Csr g = csr_from_edges(e.n, e.src, e.dst);
  const Csr in = transpose(g);
  const std::uint32_t source = *rc::gen::inRange<std::uint32_t>(0, static_cast<std::uint32_t>(e.n));
  const int threads = *rc::gen::element(1, 2, 7);
  const BfsResult ours = with_threads(threads, [&] { return bfs(g, in, {source}); });
  const BfsResult lazy = with_threads(threads, [&] { return bfs(g, {source}); });  // builds `in` if needed
  RC_ASSERT(lazy.level == ours.level);
  RC_ASSERT(lazy.parent == ours.parent);

  BoostGraph bg(e.n);
  for (std::size_t k = 0; k < e.src.size(); ++k) boost::add_edge(e.src[k], e.dst[k], bg);
  std::vector<int> level(e.n, -1);
  level[source] = 0;
  boost::breadth_first_search(bg, source,
                              boost::visitor(boost::make_bfs_visitor(
                                  boost::record_distances(level.data(), boost::on_tree_edge()))));
  for (std::size_t v = 0; v < e.n; ++v) {
    RC_ASSERT(ours.level[v] == level[v]);
    if (ours.level[v] <= 0) {
      RC_ASSERT(ours.parent[v] == kNoParent);
      continue;
    }
    // parent = the lowest id among in-neighbours one level up
    std::uint32_t expect = kNoParent;
    for (std::size_t k = 0; k < e.src.size(); ++k)
      if (e.dst[k] == v && ours.level[e.src[k]] == ours.level[v] - 1) expect = std::min(expect, e.src[k]);
    RC_ASSERT(ours.parent[v] == expect);
  }
}

RC_GTEST_PROP(graph, ComponentsEqualBoostsPartitionLabelledByLowestId, ()) {
  const Edges e = *gen_graph();
  const Csr g = csr_from_edges(e.n, e.src, e.dst);
  const std::vector<std::uint32_t> comp = components(undirected(g));

  boost::adjacency_list<boost::vecS, boost::vecS, boost::undirectedS> ug(e.n);
  for (std::size_t k = 0; k < e.src.size(); ++k) boost::add_edge(e.src[k], e.dst[k], ug);
  std::vector<int> bc(e.n);
  boost::connected_components(ug, bc.data());
  std::map<int, std::uint32_t> lowest;
  for (std::size_t v = 0; v < e.n; ++v)
    if (!lowest.count(bc[v])) lowest[bc[v]] = static_cast<std::uint32_t>(v);
  for (std::size_t v = 0; v < e.n; ++v) RC_ASSERT(comp[v] == lowest[bc[v]]);
}

// The run's components (union-find over the directed edges, no undirected CSR) are the
// undirected graph's, label for label.
RC_GTEST_PROP(graph, EdgeComponentsAreTheUndirectedGraphs, ()) {
  const Edges e = *gen_graph();
  const Csr g = csr_from_edges(e.n, e.src, e.dst);
  RC_ASSERT(edge_components(g) == components(undirected(g)));
}

TEST(graph, LargeFrontierTakesTheParallelPathAndAgrees) {
  // A star: one source with 50000 children, each with one child -> frontier of 50000.
  const std::uint32_t k = 50000;
  std::vector<std::uint32_t> src, dst;
  for (std::uint32_t i = 1; i <= k; ++i) src.push_back(0), dst.push_back(i);
  for (std::uint32_t i = 1; i <= k; ++i) src.push_back(i), dst.push_back(k + 1 + (i - 1) / 2);
  const std::size_t n = k + 1 + k / 2;
  const Csr g = csr_from_edges(n, src, dst);
  const BfsResult a = with_threads(1, [&] { return bfs(g, transpose(g), {0}); });
  const BfsResult b = with_threads(7, [&] { return bfs(g, transpose(g), {0}); });
  EXPECT_EQ(a.level, b.level);
  EXPECT_EQ(a.parent, b.parent);
  EXPECT_EQ(a.max_level, 2);
  EXPECT_EQ(a.parent[k + 1], 1u);  // children 1 and 2 both reach k+1: the lowest wins
}

// The direction-optimizing BFS expands a level bottom-up only on graphs above 2^17
// vertices and only when the level is dense; random digraphs of that size below it, and the
// properties above, never get there. 150,001 vertices with 10 out-edges each: the levels
// grow tenfold, so the middle ones are dense. Levels against Boost, parents against the
// lowest-id rule from the out-lists, both on 1 and 2 threads, and against the accelerator's
// two BFS kernels (its CPU-emulated build).
TEST(graph, BottomUpLevelsEqualBoostTheParentRuleAndTheAccelerator) {
  const std::size_t n = (std::size_t{1} << 17) + 18929;
  const Csr g = random_digraph(n, 10 * n, 2017, core::Stream::kValidation, 3);
  const Csr in = transpose(g);
  const std::vector<std::uint32_t> sources{5, 77777};
  const BfsResult one = with_threads(1, [&] { return bfs(g, in, sources); });
  const BfsResult two = with_threads(2, [&] { return bfs(g, in, sources); });
  ASSERT_GT(one.bottom_up_levels, 0) << "no level ran bottom-up: the test does not cover that branch";
  EXPECT_LT(one.bottom_up_levels, one.max_level + 1) << "no level ran top-down";
  EXPECT_EQ(two.bottom_up_levels, one.bottom_up_levels);
  EXPECT_EQ(two.level, one.level);
  EXPECT_EQ(two.parent, one.parent);
  // The overload that builds the transpose at the first bottom-up level: the same search.
  const BfsResult lazy = with_threads(2, [&] { return bfs(g, sources); });
  EXPECT_EQ(lazy.bottom_up_levels, one.bottom_up_levels);
  EXPECT_EQ(lazy.level, one.level);
  EXPECT_EQ(lazy.parent, one.parent);
  std::printf("%d of %d levels bottom-up\n", one.bottom_up_levels, one.max_level + 1);

  // Boost, from a multi-source BFS (one queue seeded with both sources).
  BoostGraph bg(n);
  for (std::size_t u = 0; u < n; ++u)
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) boost::add_edge(u, g.targets[k], bg);
  std::vector<int> level(n, -1);
  for (std::uint32_t s : sources) level[s] = 0;
  std::vector<boost::default_color_type> color(n, boost::white_color);
  boost::queue<BoostGraph::vertex_descriptor> queue;
  boost::breadth_first_search(
      bg, sources.begin(), sources.end(), queue,
      boost::make_bfs_visitor(boost::record_distances(level.data(), boost::on_tree_edge())), color.data());
  EXPECT_EQ(one.level, std::vector<std::int32_t>(level.begin(), level.end()));

  // Parent = the lowest id among the in-neighbours one level up, found from the out-lists.
  std::vector<std::uint32_t> expect(n, kNoParent);
  for (std::size_t u = 0; u < n; ++u)
    for (std::uint32_t k = g.offsets[u]; k < g.offsets[u + 1]; ++k) {
      const std::uint32_t v = g.targets[k];
      if (one.level[u] >= 0 && one.level[v] == one.level[u] + 1) expect[v] = std::min(expect[v], static_cast<std::uint32_t>(u));
    }
  EXPECT_EQ(one.parent, expect);
  std::size_t reached = 0;
  for (std::int32_t l : one.level) reached += l >= 0;
  EXPECT_EQ(one.reached, reached);
  EXPECT_GT(reached, n / 2);

  for (const BfsResult& r : {accel::bfs_queue(g, sources, false), accel::bfs_level_sync(g, sources, false)}) {
    EXPECT_EQ(r.level, one.level);
    EXPECT_EQ(r.parent, one.parent);
    EXPECT_EQ(r.max_level, one.max_level);
    EXPECT_EQ(r.reached, one.reached);
  }
}

TEST(graph, MultipleSourcesAndUnreached) {
  const Csr g = csr_from_edges(5, {0, 1, 3}, {1, 2, 4});
  const BfsResult r = bfs(g, transpose(g), {0, 3});
  EXPECT_EQ(r.level, (std::vector<std::int32_t>{0, 1, 2, 0, 1}));
  EXPECT_EQ(r.parent, (std::vector<std::uint32_t>{kNoParent, 0, 1, kNoParent, 3}));
  const BfsResult none = bfs(csr_from_edges(3, {}, {}), csr_from_edges(3, {}, {}), {1});
  EXPECT_EQ(none.level, (std::vector<std::int32_t>{-1, 0, -1}));
  EXPECT_EQ(none.reached, 1u);
}

}  // namespace
}  // namespace axg
