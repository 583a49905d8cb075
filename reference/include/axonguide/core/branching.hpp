#pragma once
// Branching and elongation of growth cones (SPEC §3.8; docs/methods.md §2.11): van Pelt &
// Uylings' BESTL model (van Pelt, Dityatev & Uylings 1997, J Comp Neurol 387:325; van Pelt &
// Uylings 2002, Network 13:261; NETMORPH, Koene et al. 2009, Neuroinformatics 7:195).
//
// Growth cone i of a tree with n cones branches at the rate
//     D(t) n^(-E) 2^(-S gamma_i) / C(t),   C(t) = (1/n) sum_j 2^(-S gamma_j),
// D(t) = B_inf e^(-t/tau) / tau (B_inf: the expected branching events of an isolated
// segment), or, with an infinite tau, the constant B_inf / period over the growth period.
// gamma_i is the cone's centrifugal order (0 on a stem; each branching adds 1 to both
// daughters). C normalises the order weights, so the tree's total rate n D(t) n^(-E) does
// not depend on S. A cone elongates at v0 n^(-F).
//
// The rule per step (a rate in physical time, so refining dt converges): over [t, t + dt],
// with n, gamma and C held at the step's start, the cone branches with probability
// 1 - exp(-x), x = (integral of D over the step) n^(-E) 2^(-S gamma) / C; the integral of
// D is exact. What remains of the discretisation (n and C fixed within a step, at most one
// branching per cone per step) is first order in dt; validate branching measures it.
#include <cstdint>

#include "hd.hpp"
#include "pmath.hpp"
#include "random.hpp"

namespace axg::core {

struct BranchingParams {
  double b_inf = 0;   // B_inf
  double e = 0;       // E (>= 0)
  double s = 0;       // S
  double tau = 0;     // time units; <= 0: infinite
  double period = 1;  // with an infinite tau: the period over which B_inf is expected (time units)
};

struct ElongationParams {
  double v0 = 0;  // length per time unit, for a tree of one cone
  double f = 0;   // F: competition, v0 n^(-F)
};

inline constexpr double kLn2 = 0x1.62e42fefa39efp-1;

// The integral of D(t) over [t0, t1].
AXG_HDI double baseline_integral(const BranchingParams& p, double t0, double t1) {
  if (!(p.tau > 0)) return p.b_inf * (t1 - t0) / p.period;
  return p.b_inf * (pm::exp(-t0 / p.tau) - pm::exp(-t1 / p.tau));
}

// 2^(-S gamma): exactly 1 for S = 0.
AXG_HDI double order_weight(double s, int order) {
  return s == 0.0 ? 1.0 : pm::exp(-s * static_cast<double>(order) * kLn2);
}

// n^(-x) for n >= 1: exactly 1 for n = 1 or x = 0.
AXG_HDI double competition(double x, int n) {
  return (n == 1 || x == 0.0) ? 1.0 : pm::exp(-x * pm::log(static_cast<double>(n)));
}

// C = (1/n) sum_j 2^(-S gamma_j) from the tree's order histogram (counts[g]: the cones of
// order g), summed in increasing order. Integer counts merge exactly in any order, so C is
// the same whether a tree's cones are stepped by one thread, many, or several ranks.
AXG_HDI double mean_order_weight(double s, const int* counts, int orders, int n) {
  double sum = 0;
  for (int g = 0; g < orders; ++g)
    if (counts[g] != 0) sum += static_cast<double>(counts[g]) * order_weight(s, g);
  return sum / static_cast<double>(n);
}

// The part of the branching exponent shared by a tree's cones over [t0, t0 + dt]: the
// integral of D times n^-E.
AXG_HDI double tree_branching(const BranchingParams& p, double t0, double dt, int n) {
  return baseline_integral(p, t0, t0 + dt) * competition(p.e, n);
}

// The probability that a cone of order `order` branches, from its tree's tree_branching and
// mean order weight: 1 - exp(-x), x = tree_branching 2^(-S order) / C.
AXG_HDI double cone_branch_probability(double tree, double s, int order, double mean_weight) {
  return 1.0 - pm::exp(-(tree * order_weight(s, order) / mean_weight));
}

// The probability that a cone of order `order` branches in [t0, t0 + dt], in a tree of n
// cones whose order weights average `mean_weight`.
AXG_HDI double branch_probability(const BranchingParams& p, double t0, double dt, int n, int order,
                                  double mean_weight) {
  return cone_branch_probability(tree_branching(p, t0, dt, n), p.s, order, mean_weight);
}

// The length a cone of a tree of n cones grows in dt.
AXG_HDI double elongation(const ElongationParams& p, int n, double dt) { return p.v0 * competition(p.f, n) * dt; }

// A cone's key for its random numbers: neuron (< 2^32) and the cone's index within its
// neuron (< 2^24), which counts the neuron's cones in the order (birth step, parent's
// index, daughter index): a function of the tree, never of the thread schedule.
inline constexpr std::uint32_t kConesPerNeuron = 1u << 24;
AXG_HDI std::uint64_t cone_key(std::uint32_t neuron, std::uint32_t index) {
  return (static_cast<std::uint64_t>(neuron) << 24) | index;
}

// Does the cone branch in this step: one uniform draw on (seed, kBranch, cone, step).
AXG_HDI bool branches(double probability, std::uint64_t seed, std::uint64_t key, std::uint32_t step) {
  Rng rng(seed, Stream::kBranch, key, step);
  return rng.uniform() < probability;
}

}  // namespace axg::core
