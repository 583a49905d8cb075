// The topology of growth-cone trees under core/branching.hpp (docs/methods.md §2.11).
#include "axonguide/morphology/tree_process.hpp"

#include <stdexcept>

#include <tbb/parallel_for.h>

namespace axg::morphology {

TreeOutcome grow_tree(const TreeProcess& p, std::uint32_t tree) {
  struct Cone {
    std::uint32_t index;
    int order;
    double segment;  // the length of its current segment
  };
  std::vector<Cone> cones{{0, 0, 0.0}}, next, daughters;
  std::vector<int> by_order{1};  // cones per centrifugal order (core::mean_order_weight)
  std::vector<int> born;         // orders of the cones that branched this step
  std::uint32_t count = 1;  // cones this tree has had
  TreeOutcome out;
  for (std::uint32_t k = 0; k < p.steps; ++k) {
    const int n = static_cast<int>(cones.size());
    const double mean_weight =
        core::mean_order_weight(p.branching.s, by_order.data(), static_cast<int>(by_order.size()), n);
    const double grow = core::elongation(p.elongation, n, p.dt);
    const double t0 = static_cast<double>(k) * p.dt;
    out.cone_steps += n;
    // Survivors keep their indices; daughters take the next ones in their parents' order,
    // so survivors then daughters is index order.
    next.clear();
    daughters.clear();
    born.clear();
    for (Cone& c : cones) {
      c.segment += grow;
      out.total_length += grow;
      const double q = core::branch_probability(p.branching, t0, p.dt, n, c.order, mean_weight);
      if (core::branches(q, p.seed, core::cone_key(tree, c.index), k)) {
        ++out.branch_points;
        out.intermediate_length += c.segment;
        for (int d = 0; d < 2; ++d) {
          if (count >= core::kConesPerNeuron) throw std::runtime_error("tree process: more than 2^24 cones in a tree");
          daughters.push_back({count++, c.order + 1, 0.0});
        }
        born.push_back(c.order);
      } else {
        next.push_back(c);
      }
    }
    next.insert(next.end(), daughters.begin(), daughters.end());
    // The histogram after the step: each branching cone of order g leaves two of order g + 1.
    for (const int g : born) {
      --by_order[static_cast<std::size_t>(g)];
      if (by_order.size() < static_cast<std::size_t>(g) + 2) by_order.resize(static_cast<std::size_t>(g) + 2, 0);
      by_order[static_cast<std::size_t>(g) + 1] += 2;
    }
    cones.swap(next);
  }
  out.terminals = static_cast<int>(cones.size());
  for (const Cone& c : cones) out.terminal_length += c.segment;
  return out;
}

std::vector<TreeOutcome> grow_trees(const TreeProcess& p, std::uint32_t count) {
  std::vector<TreeOutcome> out(count);
  tbb::parallel_for(std::uint32_t{0}, count, [&](std::uint32_t t) { out[t] = grow_tree(p, t); });
  return out;
}

}  // namespace axg::morphology
