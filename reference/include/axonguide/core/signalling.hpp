#pragma once
// Growth-cone signalling (SPEC §3.7; docs/methods.md §2.10), after Bicknell, Pujic, Dayan &
// Goodhill 2018 (PLoS Comput Biol 14:e1006218, Table 1 and its Fig 5 model). Each axon
// carries an intracellular network whose output sets its extension rate:
//
//   A   activated receptors at the growth cone (of A_t), driven by C at the tip;
//   Ac  A's signal transported to the cell body;
//   Ic  the cell-body inhibitory signal I transported to the growth cone;
//   X, Zx / Y, Zy   the gradient readout: X grows with Ac and is removed by Zx, which needs
//       both Ac and I; Y likewise with I; so X and Y compare tip and cell body;
//   F   a Goldbeter-Koshland switch (of F_t) pushed up by X and down by Y;
//   G, Gs  a growth-promoting state, made at a0 + aF F, activated by A (and, as an
//       extension, at an NGF-independent rate a1b; 0 in the paper), deactivated by Ic;
//   R   the axon's length: R' = r0 + kext Gs.
//
// The inhibitory signal I is an input: the cell-body receptors driven by C at the soma
// (I' = kpI C_soma (I_t - I) - kmI I, integrated exactly per neuron, soma_receptor_step)
// or, in an explant, their mean over the population (inhibitory signalling among the cell
// bodies). Rates are per time unit of the scene, concentrations in its unit (the scene's
// parser converts Table 1's per-minute, per-nM values). Integrated by ROS2
// (rosenbrock.hpp) at fixed work; positivity of every species and F <= F_t are checked.
#include <cmath>
#include <cstdint>

#include "hd.hpp"
#include "pmath.hpp"
#include "rosenbrock.hpp"

namespace axg::core {

inline constexpr int kSignalSpecies = 11;  // A, Ac, Ic, X, Y, Zx, Zy, F, G, Gs, R
enum SignalSpecies : int { kSA = 0, kSAc, kSIc, kSX, kSY, kSZx, kSZy, kSF, kSG, kSGs, kSR };

struct SignallingParams {
  double At, It;             // receptor totals (counts)
  double kpA, kmA, kpI, kmI; // receptor on (per concentration per time) and off (per time) rates
  double kr, kdegA;          // A's transport to the cell body and its signal's decay (per time)
  double ka, kdegI;          // I's transport to the growth cone and its decay (per time)
  double a2, b2, a3, b3;     // X and Y production (per time) and removal (per time)
  double a4, b4, a5, b5;     // Zx, Zy production (per count per time) and removal (per time)
  double g1, g2;             // Z-X and Z-Y annihilation (per count per time)
  double Ft, a6, b6, kX, kY; // the switch: total, up and down rates (per time), Michaelis constants (counts)
  double a0, aF, a1, b1, b0; // G production (per time; per F per time), activation, deactivation, decay
  double a1b;                // NGF-independent activation of G (per time; 0 in the paper, an extension)
  double r0, kext;           // basal growth (length per time), growth per Gs (length per time)
};

inline constexpr double kSignalSlack = 1e-6;

// One axon's network with its inputs held over a step: C at the tip and the inhibitory
// signal I. The interface of ros2_step.
struct SignallingSystem {
  const SignallingParams* p;
  double c;  // concentration at the tip
  double i;  // inhibitory signal (count)

  AXG_HDI int size() const { return kSignalSpecies; }
  AXG_HDI double floor(int) const { return 0.0; }
  AXG_HDI double ceiling(int s) const { return s == kSF ? p->Ft : (s == kSA ? p->At : HUGE_VAL); }
  // 10^-6 molecules (R: 10^-6 of the length unit): a species' excursion past its bound by
  // less is set to the bound (rosenbrock.hpp; docs/methods.md §2.10).
  AXG_HDI double slack(int) const { return kSignalSlack; }

  AXG_HDI void rhs(const double* y, double* f) const {
    const SignallingParams& q = *p;
    const double u = q.Ft - y[kSF];
    f[kSA] = q.kpA * c * (q.At - y[kSA]) - q.kmA * y[kSA];
    f[kSAc] = q.kr * y[kSA] - q.kdegA * y[kSAc];
    f[kSIc] = q.ka * i - q.kdegI * y[kSIc];
    f[kSX] = q.a2 * y[kSAc] - q.b2 * y[kSX] - q.g1 * y[kSZx] * y[kSX];
    f[kSY] = q.a3 * i - q.b3 * y[kSY] - q.g2 * y[kSZy] * y[kSY];
    f[kSZx] = q.a4 * y[kSAc] * i - q.b4 * y[kSZx] - q.g1 * y[kSZx] * y[kSX];
    f[kSZy] = q.a5 * y[kSAc] * i - q.b5 * y[kSZy] - q.g2 * y[kSZy] * y[kSY];
    f[kSF] = q.a6 * y[kSX] * u / (q.kX + u) - q.b6 * y[kSY] * y[kSF] / (q.kY + y[kSF]);
    f[kSG] = q.a0 + q.aF * y[kSF] - (q.a1 * y[kSA] + q.a1b) * y[kSG] + q.b1 * y[kSIc] * y[kSGs] - q.b0 * y[kSG];
    f[kSGs] = (q.a1 * y[kSA] + q.a1b) * y[kSG] - q.b1 * y[kSIc] * y[kSGs] - q.b0 * y[kSGs];
    f[kSR] = q.r0 + q.kext * y[kSGs];
  }

  // The linear solves of ROS2 with W = I - h J(y), by W's structure: J is block lower
  // triangular in the order A, Ic, Ac, (X, Zx), (Y, Zy), F, (G, Gs), R, with blocks of 1 or 2
  // species, so W x = b is a forward substitution with 2 x 2 solves by Cramer's rule. For
  // non-negative species every pivot is >= 1 and each 2 x 2 determinant >= 1 (each is 1 plus
  // sums of products of non-negative rates), so W is never singular. About 100 operations,
  // against about 900 for dense LU of 11 x 11 and its two solves.
  struct Factor {
    double h;
    double dA, dIc, dAc, wAcA;                       // pivots, and Ac's coupling to A
    double xx, xz, zx, zz, xAc, zAc, detX;           // (X, Zx): W block, couplings to Ac
    double yy, yz, zy, zzy, zyAc, detY;              // (Y, Zy)
    double dF, fX, fY;                               // F, its couplings to X and Y
    double gg, ggs, sg, ss, gF, gA, gIc, sA, sIc, detG;  // (G, Gs)
    double rGs;                                      // R's coupling to Gs
  };

  AXG_HDI bool factor(const double* y, double h, Factor& w) const {
    const SignallingParams& q = *p;
    w.h = h;
    w.dA = 1.0 + h * (q.kpA * c + q.kmA);
    w.dIc = 1.0 + h * q.kdegI;
    w.dAc = 1.0 + h * q.kdegA;
    w.wAcA = h * q.kr;
    w.xx = 1.0 + h * (q.b2 + q.g1 * y[kSZx]);
    w.xz = h * (q.g1 * y[kSX]);
    w.zx = h * (q.g1 * y[kSZx]);
    w.zz = 1.0 + h * (q.b4 + q.g1 * y[kSX]);
    w.xAc = h * q.a2;
    w.zAc = h * (q.a4 * i);
    w.detX = w.xx * w.zz - w.xz * w.zx;
    w.yy = 1.0 + h * (q.b3 + q.g2 * y[kSZy]);
    w.yz = h * (q.g2 * y[kSY]);
    w.zy = h * (q.g2 * y[kSZy]);
    w.zzy = 1.0 + h * (q.b5 + q.g2 * y[kSY]);
    w.zyAc = h * (q.a5 * i);
    w.detY = w.yy * w.zzy - w.yz * w.zy;
    const double u = q.Ft - y[kSF], ku = q.kX + u, kf = q.kY + y[kSF];
    w.dF = 1.0 + h * (q.a6 * y[kSX] * q.kX / (ku * ku) + q.b6 * y[kSY] * q.kY / (kf * kf));
    w.fX = h * (q.a6 * u / ku);
    w.fY = -h * (q.b6 * y[kSF] / kf);
    const double k = q.a1 * y[kSA] + q.a1b;
    w.gg = 1.0 + h * (k + q.b0);
    w.ggs = -h * (q.b1 * y[kSIc]);
    w.sg = -h * k;
    w.ss = 1.0 + h * (q.b1 * y[kSIc] + q.b0);
    w.gF = h * q.aF;
    w.gA = -h * (q.a1 * y[kSG]);
    w.gIc = h * (q.b1 * y[kSGs]);
    w.sA = h * (q.a1 * y[kSG]);
    w.sIc = -h * (q.b1 * y[kSGs]);
    w.detG = w.gg * w.ss - w.ggs * w.sg;
    w.rGs = h * q.kext;
    return w.detX > 0.0 && w.detY > 0.0 && w.detG > 0.0 && w.dF > 0.0;
  }

  // b <- W^-1 b: rows of W are (I - hJ), so each row's coupling terms move to the right
  // with the sign of +hJ.
  AXG_HDI void solve(const Factor& w, double* b) const {
    b[kSA] = b[kSA] / w.dA;
    b[kSIc] = b[kSIc] / w.dIc;
    b[kSAc] = (b[kSAc] + w.wAcA * b[kSA]) / w.dAc;
    const double rx = b[kSX] + w.xAc * b[kSAc], rz = b[kSZx] + w.zAc * b[kSAc];
    b[kSX] = (rx * w.zz - w.xz * rz) / w.detX;
    b[kSZx] = (w.xx * rz - w.zx * rx) / w.detX;
    const double ry = b[kSY], rzy = b[kSZy] + w.zyAc * b[kSAc];
    b[kSY] = (ry * w.zzy - w.yz * rzy) / w.detY;
    b[kSZy] = (w.yy * rzy - w.zy * ry) / w.detY;
    b[kSF] = (b[kSF] + w.fX * b[kSX] + w.fY * b[kSY]) / w.dF;
    const double rg = b[kSG] + w.gF * b[kSF] + w.gA * b[kSA] + w.gIc * b[kSIc];
    const double rs = b[kSGs] + w.sA * b[kSA] + w.sIc * b[kSIc];
    b[kSG] = (rg * w.ss - w.ggs * rs) / w.detG;
    b[kSGs] = (w.gg * rs - w.sg * rg) / w.detG;
    b[kSR] = b[kSR] + w.rGs * b[kSGs];
  }

  // Row-major df_i / dy_j.
  AXG_HDI void jacobian(const double* y, double* j) const {
    const SignallingParams& q = *p;
    const int n = kSignalSpecies;
    for (int k = 0; k < n * n; ++k) j[k] = 0.0;
    const double u = q.Ft - y[kSF];
    j[kSA * n + kSA] = -q.kpA * c - q.kmA;
    j[kSAc * n + kSA] = q.kr;
    j[kSAc * n + kSAc] = -q.kdegA;
    j[kSIc * n + kSIc] = -q.kdegI;
    j[kSX * n + kSAc] = q.a2;
    j[kSX * n + kSX] = -q.b2 - q.g1 * y[kSZx];
    j[kSX * n + kSZx] = -q.g1 * y[kSX];
    j[kSY * n + kSY] = -q.b3 - q.g2 * y[kSZy];
    j[kSY * n + kSZy] = -q.g2 * y[kSY];
    j[kSZx * n + kSAc] = q.a4 * i;
    j[kSZx * n + kSZx] = -q.b4 - q.g1 * y[kSX];
    j[kSZx * n + kSX] = -q.g1 * y[kSZx];
    j[kSZy * n + kSAc] = q.a5 * i;
    j[kSZy * n + kSZy] = -q.b5 - q.g2 * y[kSY];
    j[kSZy * n + kSY] = -q.g2 * y[kSZy];
    const double ku = q.kX + u, kf = q.kY + y[kSF];
    j[kSF * n + kSX] = q.a6 * u / ku;
    j[kSF * n + kSY] = -q.b6 * y[kSF] / kf;
    j[kSF * n + kSF] = -q.a6 * y[kSX] * q.kX / (ku * ku) - q.b6 * y[kSY] * q.kY / (kf * kf);
    j[kSG * n + kSF] = q.aF;
    j[kSG * n + kSA] = -q.a1 * y[kSG];
    j[kSG * n + kSG] = -(q.a1 * y[kSA] + q.a1b) - q.b0;
    j[kSG * n + kSIc] = q.b1 * y[kSGs];
    j[kSG * n + kSGs] = q.b1 * y[kSIc];
    j[kSGs * n + kSA] = q.a1 * y[kSG];
    j[kSGs * n + kSG] = q.a1 * y[kSA] + q.a1b;
    j[kSGs * n + kSIc] = -q.b1 * y[kSGs];
    j[kSGs * n + kSGs] = -q.b1 * y[kSIc] - q.b0;
    j[kSR * n + kSGs] = q.kext;
  }
};

// The positive root of x^2 + p x - q = 0 (q >= 0), without cancellation.
AXG_HDI double positive_root(double p, double q) {
  const double d = std::sqrt(p * p + 4.0 * q);
  return p > 0.0 ? 2.0 * q / (p + d) : 0.5 * (d - p);
}

// Receptor occupancy at steady state: total x c / (c + K), K = off / on.
AXG_HDI double bound_receptors(double total, double on, double off, double c) {
  const double k = off / on;
  return c > 0.0 ? total * c / (c + k) : 0.0;
}

// The network's steady state with C = c at the tip and inhibitory signal i (R = 0): the
// initial condition of every axon, with c and i those of its cell body (Bicknell et al.'s
// closed forms: each pair (X, Zx), (Y, Zy) solves a quadratic, F the Goldbeter-Koshland
// function, G + Gs = (a0 + aF F) / b0).
AXG_HDI void signalling_steady_state(const SignallingParams& q, double c, double i, double* y) {
  const double a = bound_receptors(q.At, q.kpA, q.kmA, c);
  const double ac = q.kr / q.kdegA * a;
  const double ic = q.ka / q.kdegI * i;
  const double x = positive_root(q.b4 / q.g1 + ac * (q.a4 * i - q.a2) / q.b2, q.a2 * ac * q.b4 / (q.b2 * q.g1));
  const double yy = positive_root(q.b5 / q.g2 + i * (q.a5 * ac - q.a3) / q.b3, q.a3 * i * q.b5 / (q.b3 * q.g2));
  const double zx = q.a4 * ac * i / (q.b4 + q.g1 * x);
  const double zy = q.a5 * ac * i / (q.b5 + q.g2 * yy);
  // Goldbeter-Koshland: v1 (1 - f) / (J1 + 1 - f) = v2 f / (J2 + f), f = F / F_t.
  const double v1 = q.a6 * x, v2 = q.b6 * yy, j1 = q.kX / q.Ft, j2 = q.kY / q.Ft;
  const double b = v2 - v1 + j1 * v2 + j2 * v1;
  const double disc = b * b - 4.0 * (v2 - v1) * v1 * j2;
  const double den = b + std::sqrt(disc > 0.0 ? disc : 0.0);
  const double f = den > 0.0 ? 2.0 * v1 * j2 / den : (v1 > 0.0 ? 1.0 : 0.0);
  const double F = q.Ft * f;
  const double total = (q.a0 + q.aF * F) / q.b0;
  const double gs = total * (q.a1 * a + q.a1b) / (q.a1 * a + q.a1b + q.b1 * ic + q.b0);
  y[kSA] = a, y[kSAc] = ac, y[kSIc] = ic, y[kSX] = x, y[kSY] = yy, y[kSZx] = zx, y[kSZy] = zy;
  y[kSF] = F, y[kSG] = total - gs, y[kSGs] = gs, y[kSR] = 0.0;
}

// The cell-body receptors over a step of length dt at soma concentration c, exactly:
// I -> I_inf + (I - I_inf) e^(-(kpI c + kmI) dt).
AXG_HDI double soma_receptor_step(const SignallingParams& q, double i, double c, double dt) {
  const double rate = q.kpI * c + q.kmI;
  const double inf = rate > 0.0 ? q.It * q.kpI * c / rate : 0.0;
  return inf + (i - inf) * pm::exp(-rate * dt);
}

// The explant's inhibitory signal: the mean of its cell bodies' receptors [first, end)
// (summed in id order), written to each of them. Both engines call this.
AXG_HDI void population_inhibition(const double* receptors, std::uint64_t first, std::uint64_t end,
                                   double* inhibition) {
  double sum = 0.0;
  for (std::uint64_t i = first; i < end; ++i) sum += receptors[i];
  const double mean = sum / static_cast<double>(end - first);
  for (std::uint64_t i = first; i < end; ++i) inhibition[i] = mean;
}

struct SignallingStep {
  StiffStatus status;
  int species;   // the first species that failed, or -1
  double grown;  // length grown over the step (R's increase)
};

// The halvings a failed sub-step may take by default: down to 1/1024 of it.
inline constexpr int kSignalHalvings = 10;

// One growth step of one axon: `substeps` ROS2 steps of dt / substeps with C = c at the tip
// and inhibitory signal i. A sub-step that fails (a species leaves its range, a result not
// finite, a singular W) is redone as two steps of half its length, each of which may again
// be halved, down to 2^-halvings of the sub-step (docs/methods.md §2.10). The pieces are
// taken in time order and the decision to halve depends only on the state, so the work and
// the bytes are the same on every backend and thread count; a scene whose steps all succeed
// is unchanged. Only when a piece of the smallest length fails does the step fail; the
// state is then left at the last good piece.
AXG_HDI SignallingStep signalling_step(const SignallingParams& q, double* y, double c, double i, double dt,
                                       int substeps, int halvings = kSignalHalvings) {
  const SignallingSystem sys{&q, c, i};
  const double tau = dt / static_cast<double>(substeps);
  const double r_before = y[kSR];
  // Positions within a sub-step in units of tau / 2^halvings; a piece at `level` spans
  // 2^(halvings - level) units and has length tau / 2^level (exact: halving is exact).
  const std::uint32_t units = std::uint32_t{1} << halvings;
  for (int s = 0; s < substeps; ++s) {
    std::uint32_t pos = 0;
    int level = 0;
    double h = tau;
    while (pos < units) {
      int species = -1;
      const StiffStatus st = ros2_step(sys, y, h, &species);
      if (st == StiffStatus::kOk) {
        pos += std::uint32_t{1} << (halvings - level);
        // Back to the longer piece once both of its halves are done.
        while (level > 0 && pos % (std::uint32_t{1} << (halvings - level + 1)) == 0) --level, h = h * 2.0;
      } else if (level < halvings) {
        ++level, h = h * 0.5;
      } else {
        return {st, species, y[kSR] - r_before};
      }
    }
  }
  return {StiffStatus::kOk, -1, y[kSR] - r_before};
}

}  // namespace axg::core
