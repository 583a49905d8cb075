#pragma once
// The particle field's estimate of C and grad C (SPEC §3.4; docs/methods.md §2.6). The
// particles are a Monte Carlo solution of the diffusion-decay equation; what a growth cone
// reads from them is an estimate of the field they sample, and the estimate's own error is
// numerical: it must vanish as the particles are refined, and it is never evidence.
//
// Each cue keeps two estimate meshes ("halves"), one for the particles of even id and one
// for those of odd id: two independent thinnings of one Poisson process, each estimating
// the whole concentration from its half (2a per particle). Every step:
//   1. deposit: every particle adds its cloud-in-cell (trilinear) weights to the 8 nodes
//      of its cell, in fixed point: weights of 2^32 per particle (the last corner takes
//      the remainder, so a particle deposits exactly 2^32). Integer sums are exact in any
//      order, so every backend and thread count gets the same bytes with no sort;
//   2. fold: every node of every half takes an exponential moving average of its deposit,
//      M <- keep M + take (scale q), with bias-corrected weights (keep, take from
//      estimate_fold) so that a steady deposit is estimated without lag from step 1;
//      scale = 2a / (h^3 2^32) turns a fixed-point count into a concentration;
//   3. sample (at a growth cone): mesh_sample (mesh.hpp) of both halves; C is their mean,
//      grad the gradient of the even half, grad_check that of the odd half. Steering takes
//      a direction from grad and the magnitude along it from grad_check (steering.hpp), so
//      the estimate's noise can only weaken a decision: in a flat field the magnitude is
//      symmetric about zero whatever the direction, and the side of the turn is a fair coin.
#include <cstddef>
#include <cstdint>

#include "cues.hpp"
#include "hd.hpp"
#include "mesh.hpp"
#include "vec3.hpp"

namespace axg::core {

// One particle's weight in fixed point.
inline constexpr double kDepositUnit = 4294967296.0;  // 2^32
inline constexpr std::uint64_t kDepositUnitInt = std::uint64_t{1} << 32;

// The meshes of every cue: half s of cue k at c + (2k + s) * nodes, node (0,0,0) of cue k's
// meshes at origin[k] (each cue's cube is centred on its source when it is smaller than the
// domain; cue_setup.cpp, estimate_geometry).
struct EstimateSet {
  double h;           // LU, node spacing
  int n;              // nodes per axis
  std::size_t nodes;  // n^3
  const double* c;    // 2 K n^3 estimates, concentration units
  Vec3 origin[kMaxCues];  // LU
};

AXG_HDI GridFieldView estimate_half(const EstimateSet& s, int cue, int half) {
  return {s.origin[cue], s.h, s.n, s.c + (2 * static_cast<std::size_t>(cue) + static_cast<std::size_t>(half)) * s.nodes, 0};
}

// The half a particle belongs to, for its whole life: the parity of its id.
AXG_HDI int estimate_half_of(std::uint64_t id) { return static_cast<int>(id & 1u); }

struct CicDeposit {
  std::size_t index[8];
  std::uint64_t weight[8];  // fixed point; they sum to exactly 2^32
};

// Whether a particle deposits: inside the mesh's span on every axis. A cue's mesh spans the
// domain, or a cube about its source many decay lengths wide (cue_setup.cpp,
// estimate_geometry); particles beyond it are too rare to matter and are left out rather
// than piled on the mesh's faces.
AXG_HDI bool cic_inside(Vec3 x, Vec3 origin, double h, int n) {
  const double span = static_cast<double>(n - 1) * h;
  const double tx = x.x - origin.x, ty = x.y - origin.y, tz = x.z - origin.z;
  return tx >= 0.0 && tx <= span && ty >= 0.0 && ty <= span && tz >= 0.0 && tz <= span;
}

// The cloud-in-cell weights of a particle at x, corners in (z, y, x) order.
AXG_HDI CicDeposit cic_deposit(Vec3 x, Vec3 origin, double h, int n) {
  int i, j, k;
  double fx, fy, fz;
  mesh_locate(x.x, origin.x, h, n, &i, &fx);
  mesh_locate(x.y, origin.y, h, n, &j, &fy);
  mesh_locate(x.z, origin.z, h, n, &k, &fz);
  const double wx[2] = {1.0 - fx, fx}, wy[2] = {1.0 - fy, fy}, wz[2] = {1.0 - fz, fz};
  CicDeposit d{};
  std::uint64_t given = 0;
  int m = 0;
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a, ++m) {
        d.index[m] = node_index(i + a, j + b, k + c, n);
        if (m == 7) break;
        const double w = (wx[a] * wy[b]) * wz[c];
        d.weight[m] = static_cast<std::uint64_t>(w * kDepositUnit);
        given += d.weight[m];
      }
  d.weight[7] = given < kDepositUnitInt ? kDepositUnitInt - given : 0;
  return d;
}

// The fold of one step (host-computed): M <- keep M + take (scale q).
struct EstimateFold {
  double keep;   // weight of the previous estimate
  double take;   // weight of this step's deposit
  double scale;  // concentration per fixed-point unit: 2a / (h^3 2^32)
};

// x^t by squaring: the same operations for the same t on every backend.
AXG_HDI double power_of(double x, std::uint32_t t) {
  double result = 1.0, base = x;
  while (t > 0) {
    if (t & 1u) result = result * base;
    base = base * base;
    t >>= 1;
  }
  return result;
}

// The bias-corrected moving average of field step t (1-based) with per-step weight beta in
// (0, 1]: with W_t = 1 - (1 - beta)^t the total weight of steps 1..t,
//   M_t = ((1 - beta) W_(t-1) M_(t-1) + beta q_t) / W_t,
// the average of q_1..q_t with weights beta (1 - beta)^(t - s) normalised to 1: a steady
// deposit is estimated without lag from the first step, and beta = 1 keeps only this step.
AXG_HDI EstimateFold estimate_fold(std::uint32_t t, double beta, double scale) {
  const double r = 1.0 - beta;
  const double w_now = 1.0 - power_of(r, t);
  const double w_before = t > 1 ? 1.0 - power_of(r, t - 1) : 0.0;
  return {r * w_before / w_now, beta / w_now, scale};
}

AXG_HDI double fold_node(double m, std::uint64_t q, const EstimateFold& f) {
  return f.keep * m + f.take * (f.scale * static_cast<double>(q));
}

// The estimate of cue k at x: C the mean of the halves, grad from the even half and
// grad_check from the odd half.
AXG_HDI CueSample estimate_sample(Vec3 x, const EstimateSet& s, int cue) {
  const MeshSample even = mesh_sample(x, estimate_half(s, cue, 0));
  const MeshSample odd = mesh_sample(x, estimate_half(s, cue, 1));
  return {0.5 * (even.value + odd.value), even.grad, odd.grad};
}

// The estimate of cue k over the sensing ball of radius r (the count form's target;
// mesh.hpp, mesh_ball_sample): the mean of the halves' means, the effective gradient of the
// even half and that of the odd half.
AXG_HDI CueSample estimate_ball_sample(Vec3 x, const EstimateSet& s, int cue, double r) {
  const MeshSample even = mesh_ball_sample(x, estimate_half(s, cue, 0), r);
  const MeshSample odd = mesh_ball_sample(x, estimate_half(s, cue, 1), r);
  return {0.5 * (even.value + odd.value), even.grad, odd.grad};
}

}  // namespace axg::core
