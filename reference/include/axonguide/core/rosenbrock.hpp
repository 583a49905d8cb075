#pragma once
// A linearly implicit, L-stable integrator of fixed work for small stiff systems
// y' = f(y) (SPEC §3.7; docs/methods.md §2.10): ROS2 of Verwer, Spee, Blom and Hundsdorfer
// (1999, SIAM J Sci Comput 20:1456), with gamma = 1 + 1/sqrt(2):
//
//   W = I - gamma tau J(y_n),
//   W k1 = f(y_n),
//   W k2 = f(y_n + tau k1) - 2 k1,
//   y_(n+1) = y_n + (3/2) tau k1 + (1/2) tau k2.
//
// Second order for any W (it is also a W-method), L-stable (its stability function tends to
// 0 at infinity), and its work is fixed: one factorisation of W (the system's own
// structured one, or dense LU with partial pivoting, DenseLinear), two solves and two
// evaluations of f per step; no Newton iteration, so nothing can fail to converge. What can fail is reported: a singular W, a result that is
// not finite, or one below the floor the system gives for a species (its positivity). Only
// + - * / and sqrt, in a fixed order: the same bytes on every backend.
#include <cstdint>

#include "hd.hpp"

namespace axg::core {

inline constexpr int kMaxStiff = 16;  // species of one system at most

// 1 + 1/sqrt(2), to the last bit (sqrt(2) correctly rounded, then one division and one add).
AXG_HDI double ros2_gamma() { return 1.0 + 1.0 / 1.4142135623730951; }

// LU factorisation of the n x n row-major matrix a in place with partial pivoting (ties:
// the lowest row), the row permutation in piv. Returns false for an exactly singular pivot.
AXG_HDI bool lu_factor(double* a, int n, int* piv) {
  for (int k = 0; k < n; ++k) {
    int p = k;
    double best = a[k * n + k] < 0 ? -a[k * n + k] : a[k * n + k];
    for (int i = k + 1; i < n; ++i) {
      const double v = a[i * n + k] < 0 ? -a[i * n + k] : a[i * n + k];
      if (v > best) best = v, p = i;
    }
    piv[k] = p;
    if (!(best > 0.0)) return false;
    if (p != k)
      for (int j = 0; j < n; ++j) {
        const double t = a[k * n + j];
        a[k * n + j] = a[p * n + j];
        a[p * n + j] = t;
      }
    for (int i = k + 1; i < n; ++i) {
      const double l = a[i * n + k] / a[k * n + k];
      a[i * n + k] = l;
      if (l != 0.0)
        for (int j = k + 1; j < n; ++j) a[i * n + j] = a[i * n + j] - l * a[k * n + j];
    }
  }
  return true;
}

// Solves (LU) x = b in place, with the factorisation and pivots of lu_factor.
AXG_HDI void lu_solve(const double* a, int n, const int* piv, double* b) {
  for (int k = 0; k < n; ++k) {
    const int p = piv[k];
    if (p != k) {
      const double t = b[k];
      b[k] = b[p];
      b[p] = t;
    }
  }
  for (int i = 1; i < n; ++i) {
    double s = b[i];
    for (int j = 0; j < i; ++j) s = s - a[i * n + j] * b[j];
    b[i] = s;
  }
  for (int i = n - 1; i >= 0; --i) {
    double s = b[i];
    for (int j = i + 1; j < n; ++j) s = s - a[i * n + j] * b[j];
    b[i] = s / a[i * n + i];
  }
}

enum class StiffStatus : std::uint8_t { kOk = 0, kSingular = 1, kNotFinite = 2, kOutOfRange = 3 };

// A system's linear solves with W = I - h J(y) by dense LU with partial pivoting: the
// generic way for a system that provides only its Jacobian (and the check of a system's own
// structured solves). `System` provides int size() and void jacobian(const double* y,
// double* j) (row-major df_i/dy_j).
struct DenseFactor {
  double w[kMaxStiff * kMaxStiff];
  int piv[kMaxStiff];
};

template <class System>
struct DenseLinear {
  const System* sys;
  using Factor = DenseFactor;
  AXG_HDI int size() const { return sys->size(); }
  AXG_HDI double floor(int i) const { return sys->floor(i); }
  AXG_HDI double ceiling(int i) const { return sys->ceiling(i); }
  AXG_HDI double slack(int i) const { return sys->slack(i); }
  AXG_HDI void rhs(const double* y, double* f) const { sys->rhs(y, f); }
  AXG_HDI bool factor(const double* y, double h, Factor& f) const {
    const int n = sys->size();
    sys->jacobian(y, f.w);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) f.w[i * n + j] = (i == j ? 1.0 : 0.0) - h * f.w[i * n + j];
    return lu_factor(f.w, n, f.piv);
  }
  AXG_HDI void solve(const Factor& f, double* b) const { lu_solve(f.w, sys->size(), f.piv, b); }
};

// One ROS2 step of size tau: `sys` provides int size(), void rhs(const double* y, double*
// f), the linear solves with W = I - gamma tau J(y) (a type Factor; bool factor(const
// double* y, double h, Factor&), false where W is singular; void solve(const Factor&,
// double* b), b <- W^-1 b in place), and double floor(int i), ceiling(int i) and slack(int
// i): the range species i must stay in (its positivity, and a total it cannot exceed), and
// how far outside it a result is the method's truncation error rather than a failure. A
// result within the slack of a bound is set to the bound (a species that starts at exactly
// 0 takes an O(tau^3) negative excursion in ROS2's second stage); one beyond it fails. y is
// updated in place; on failure it is left as it was and *species names the first offending
// species (or -1).
template <class System>
AXG_HDI StiffStatus ros2_step(const System& sys, double* y, double tau, int* species) {
  const int n = sys.size();
  const double g = ros2_gamma();
  typename System::Factor w;
  double k1[kMaxStiff], k2[kMaxStiff], y1[kMaxStiff];
  *species = -1;
  if (!sys.factor(y, g * tau, w)) return StiffStatus::kSingular;
  sys.rhs(y, k1);
  sys.solve(w, k1);
  for (int i = 0; i < n; ++i) y1[i] = y[i] + tau * k1[i];
  sys.rhs(y1, k2);
  for (int i = 0; i < n; ++i) k2[i] = k2[i] - 2.0 * k1[i];
  sys.solve(w, k2);
  double next[kMaxStiff];
  for (int i = 0; i < n; ++i) {
    next[i] = y[i] + (1.5 * tau) * k1[i] + (0.5 * tau) * k2[i];
    if (!(next[i] - next[i] == 0.0)) {  // NaN or infinite
      *species = i;
      return StiffStatus::kNotFinite;
    }
    const double lo = sys.floor(i), hi = sys.ceiling(i), slack = sys.slack(i);
    if (next[i] < lo - slack || next[i] > hi + slack) {
      *species = i;
      return StiffStatus::kOutOfRange;
    }
    if (next[i] < lo) next[i] = lo;
    if (next[i] > hi) next[i] = hi;
  }
  for (int i = 0; i < n; ++i) y[i] = next[i];
  return StiffStatus::kOk;
}

}  // namespace axg::core
