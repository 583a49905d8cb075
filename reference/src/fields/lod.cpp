#include "axonguide/fields/lod.hpp"

#include <algorithm>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "axonguide/core/stencil.hpp"

namespace axg {

namespace {

// Lines of n rows, row m of line x of plane p at c + p plane_stride + m row_stride + x:
// every line of a plane advances row by row.
void sweep_planes(double* c, int n, std::size_t planes, std::size_t row_stride, std::size_t plane_stride,
                  double lambda, bool reflecting) {
  const std::size_t nn = static_cast<std::size_t>(n);
  tbb::enumerable_thread_specific<std::vector<double>> scratch([nn] { return std::vector<double>(2 * nn * nn); });
  const core::LodLine l = core::lod_line(n, lambda, reflecting);
  tbb::parallel_for(std::size_t{0}, planes, [&](std::size_t p) {
    std::vector<double>& buf = scratch.local();
    double* cp = buf.data();
    double* dp = buf.data() + nn * nn;
    double* base = c + p * plane_stride;
    auto at = [&](int m) { return base + static_cast<std::size_t>(m) * row_stride; };
    if (!reflecting) {
      std::fill(at(0), at(0) + nn, 0.0);
      std::fill(at(n - 1), at(n - 1) + nn, 0.0);
    }
    if (l.hi < l.lo) return;
    for (int m = l.lo; m <= l.hi; ++m) {
      const double* rhs = at(m);
      double* cpm = cp + static_cast<std::size_t>(m) * nn;
      double* dpm = dp + static_cast<std::size_t>(m) * nn;
      const bool first = m == l.lo;
      for (std::size_t x = 0; x < nn; ++x)
        core::lod_forward(l, m, rhs[x], first ? 0.0 : cpm[x - nn], first ? 0.0 : dpm[x - nn], &cpm[x], &dpm[x]);
    }
    std::copy(dp + static_cast<std::size_t>(l.hi) * nn, dp + static_cast<std::size_t>(l.hi + 1) * nn, at(l.hi));
    for (int m = l.hi - 1; m >= l.lo; --m) {
      double* out = at(m);
      const double* next = at(m + 1);
      const double* cpm = cp + static_cast<std::size_t>(m) * nn;
      const double* dpm = dp + static_cast<std::size_t>(m) * nn;
      for (std::size_t x = 0; x < nn; ++x) out[x] = core::lod_backward(cpm[x], dpm[x], next[x]);
    }
  });
}

}  // namespace

void lod_sweep_x(double* c, int n, int planes, double lambda, bool reflecting) {
  const std::size_t nn = static_cast<std::size_t>(n);
  tbb::enumerable_thread_specific<std::vector<double>> scratch([nn] { return std::vector<double>(2 * nn); });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, static_cast<std::size_t>(planes) * nn),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      std::vector<double>& buf = scratch.local();
                      for (std::size_t line = r.begin(); line != r.end(); ++line)
                        core::lod_line_solve(c, line * nn, 1, n, lambda, reflecting, buf.data(), buf.data() + nn);
                    });
}

// Axis 1 (y): planes z = p, lines x = 0..n-1, row m = y.
void lod_sweep_y(double* c, int n, int planes, double lambda, bool reflecting) {
  const std::size_t nn = static_cast<std::size_t>(n);
  sweep_planes(c, n, static_cast<std::size_t>(planes), nn, nn * nn, lambda, reflecting);
}

// Axis 2 (z): planes y = p, row m = z.
void lod_sweep_z(double* c, int n, double lambda, bool reflecting) {
  const std::size_t nn = static_cast<std::size_t>(n);
  sweep_planes(c, n, nn, nn * nn, nn, lambda, reflecting);
}

void lod_sweeps(double* c, int n, double lambda, bool reflecting) {
  lod_sweep_x(c, n, n, lambda, reflecting);
  lod_sweep_y(c, n, n, lambda, reflecting);
  lod_sweep_z(c, n, lambda, reflecting);
}

}  // namespace axg
