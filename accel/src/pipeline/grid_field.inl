// The grid-field kernels: source deposit, explicit FTCS, implicit LOD line solves, decay.
// Part of the pipeline (../pipeline.inl); compiled once per build of it.
#pragma once

namespace axg::accel::AXG_ACCEL_NS {

struct Deposit {
  double* d_c;
  core::SourceDeposit d;
  AXG_HD void operator()(std::size_t) const {
    for (int m = 0; m < 8; ++m) d_c[d.index[m]] += d.value[m];
  }
};

struct Ftcs {
  const double* d_in;
  double* d_out;
  core::StencilParams s;
  AXG_HD void operator()(std::size_t idx) const {
    const std::size_t n = static_cast<std::size_t>(s.n);
    const int i = static_cast<int>(idx % n), j = static_cast<int>((idx / n) % n), k = static_cast<int>(idx / (n * n));
    d_out[idx] = core::ftcs_node(d_in, i, j, k, s);
  }
};

// One thread per line of one axis (the reference's lines: x lines contiguous; y lines of
// plane z = p, column x = q; z lines of row y = p, column x = q).
struct LodLines {
  double* d_c;
  double* d_cp;
  double* d_dp;
  int n;
  int axis;
  double lambda;
  bool reflecting;
  AXG_HD void operator()(std::size_t line) const {
    const std::size_t nn = static_cast<std::size_t>(n);
    const std::size_t p = line / nn, q = line % nn;
    std::size_t first, stride;
    if (axis == 0) first = line * nn, stride = 1;
    else if (axis == 1) first = p * nn * nn + q, stride = nn;
    else first = p * nn + q, stride = nn * nn;
    core::lod_line_solve(d_c, first, stride, n, lambda, reflecting, d_cp + line * nn, d_dp + line * nn);
  }
};

struct Scale {
  double* d_c;
  double factor;
  AXG_HD void operator()(std::size_t i) const { d_c[i] = d_c[i] * factor; }
};

}  // namespace axg::accel::AXG_ACCEL_NS
