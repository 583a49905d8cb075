// The marginal of one coordinate of a uniform point on S^(d-1): inverse CDF, CDF and pdf
// (axonguide/placement/coordinate_marginal.hpp).
//
// Tolerances, and why:
//  * Consistency of the inverse with the computed CDF ("solves F(x) = u"). The solver
//    returns one of two adjacent doubles bracketing the root of the computed F, so the
//    root of F lies within one ulp of x. Checked on the lower-tail side, where F carries a
//    relative error (p = min(u, 1-u), s = -|x|):
//        F(s - 1 ulp) <= p (1 + rho)   and   F(s + 1 ulp) >= p (1 - rho),
//    rho = 4 (d + 8) eps. rho is the noise of the computed F, not of the solver: GSL's
//    I_y((d-1)/2, 1/2) is exp(b ln y + ...) times a continued fraction, so one rounding of
//    y or of the logarithms becomes a relative error of about b eps; adjacent doubles can
//    be out of order by that much (worst seen: 1.3 (d + 8) eps). This is the discrete form
//    of |F(x) - u| <= f(x) ulp(x) + rho p, and holds down to u = 1e-300 and up to
//    1 - 2^-53.
//  * Accuracy against the truth: closed forms for d = 2 (x = -cos(pi u), 1e-12 absolute),
//    d = 3 (x = 2u - 1 within 2 ulp) and d = 5 (F = 1/2 + (3x - x^3)/4, relative 1e-13),
//    and 60-digit mpmath roots for d = 4, 10, 100, 1000 (relative 1e-14; worst seen
//    2.2e-15, i.e. 13 ulp, in the centre where x is small).
//  * Monotonicity: strict for independently drawn u1 < u2. For consecutive doubles u the
//    noise of F can reorder results by a few ulps (worst seen 30 ulp = 6e-15 relative, for
//    large d just beyond the point where GSL switches continued fractions), so there the
//    allowance is 2e-14 |x|.
#include "axonguide/placement/coordinate_marginal.hpp"

#include <gsl/gsl_sf_gamma.h>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

#include "axonguide/core/pmath.hpp"

namespace {

using axg::coordinate_marginal_cdf;
using axg::coordinate_marginal_inverse;
using axg::coordinate_marginal_inverse_detail;
using axg::coordinate_marginal_pdf;

constexpr double kPi = 3.141592653589793;
constexpr double kEps = DBL_EPSILON;
constexpr int kDims[] = {2, 3, 4, 5, 10, 50, 100, 500, 1000};

double ulp_of(double x) {
  const double a = std::fabs(x);
  return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

std::uint64_t bits_of(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// Relative noise of the computed F (see the header comment).
double noise(int d) { return 4.0 * (static_cast<double>(d) + 8.0) * kEps; }

// The values of F one ulp either side of x, mirrored to the lower tail.
struct Bracket {
  double p;      // min(u, 1 - u)
  double below;  // F(s - 1 ulp), s = -|x|
  double above;  // F(s + 1 ulp)
  double tol;    // rho p
};

Bracket bracket_of(double u, int d, double x) {
  const bool upper = u >= 0.5;
  const double p = upper ? 1.0 - u : u;  // exact
  const double s = upper ? -x : x;       // the lower-tail point, F(s) ~ p
  return {p, coordinate_marginal_cdf(std::nextafter(s, -1.0), d),
          coordinate_marginal_cdf(std::nextafter(s, 1.0), d), noise(d) * p};
}

// ---------------------------------------------------------------------------------------------
// Generators
// ---------------------------------------------------------------------------------------------

double double_of(std::uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

// u in (0, 1): uniform on the 2^-53 grid, log-uniform tails down to 2^-996 ~ 1.5e-300 on
// either side, and the edge values.
rc::Gen<double> gen_u() {
  const auto grid = rc::gen::map(rc::gen::inRange<std::uint64_t>(1, 1ull << 53),
                                 [](std::uint64_t k) { return static_cast<double>(k) * 0x1p-53; });
  const auto tail = rc::gen::apply(
      [](int field, std::uint64_t significand, bool mirror) {
        const double v = double_of(static_cast<std::uint64_t>(field) << 52 | significand);
        const double w = 1.0 - v;
        return mirror && w < 1.0 ? w : v;
      },
      rc::gen::inRange(1023 - 996, 1023), rc::gen::inRange<std::uint64_t>(0, 1ull << 52),
      rc::gen::arbitrary<bool>());
  const auto edge = rc::gen::element(1e-300, 0x1p-53, 1e-16, 1.0 - 0x1p-53, 0.5, 0.25, 0.75,
                                     std::nextafter(0.5, 0.0), std::nextafter(0.5, 1.0), 0.1, 0.9);
  return rc::gen::resize(rc::kNominalSize, rc::gen::oneOf(grid, tail, edge));
}

rc::Gen<int> gen_d() {
  return rc::gen::resize(
      rc::kNominalSize,
      rc::gen::oneOf(rc::gen::element(2, 3, 4, 5, 10, 50, 100, 500, 1000), rc::gen::inRange(2, 1001)));
}

// ---------------------------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------------------------

RC_GTEST_PROP(CoordinateMarginal, PropertyInverseSolvesCdf, ()) {
  const double u = *gen_u();
  const int d = *gen_d();
  const auto solved = coordinate_marginal_inverse_detail(u, d);
  const double x = solved.x;
  RC_ASSERT(x >= -1.0);
  RC_ASSERT(x <= 1.0);
  RC_ASSERT(solved.iterations <= 40);  // worst seen over 2e5 random cases: 17
  const Bracket b = bracket_of(u, d, x);
  RC_ASSERT(b.below <= b.p + b.tol);
  RC_ASSERT(b.above >= b.p - b.tol);
}

RC_GTEST_PROP(CoordinateMarginal, PropertyMonotoneInU, ()) {
  double u1 = *gen_u();
  double u2 = *gen_u();
  const int d = *gen_d();
  RC_PRE(u1 != u2);
  if (u1 > u2) std::swap(u1, u2);
  RC_ASSERT(coordinate_marginal_inverse(u1, d) <= coordinate_marginal_inverse(u2, d));
}

// x(1 - u) = -x(u) bit for bit (up to the sign of zero) whenever 1 - u is exact.
RC_GTEST_PROP(CoordinateMarginal, PropertyOddSymmetry, ()) {
  const double u = *gen_u();
  const int d = *gen_d();
  const double v = 1.0 - u;
  RC_PRE(v > 0.0 && v < 1.0 && 1.0 - v == u);
  RC_ASSERT(coordinate_marginal_inverse(v, d) == -coordinate_marginal_inverse(u, d));
}

RC_GTEST_PROP(CoordinateMarginal, PropertyDimension3IsLinear, ()) {
  const double u = *gen_u();
  const double x = coordinate_marginal_inverse(u, 3);
  const long double exact = 2.0L * static_cast<long double>(u) - 1.0L;
  RC_ASSERT(std::fabs(static_cast<long double>(x) - exact) <=
            2.0L * static_cast<long double>(ulp_of(x)));
}

RC_GTEST_PROP(CoordinateMarginal, PropertyDimension2IsArcsine, ()) {
  const double u = *gen_u();
  RC_ASSERT(std::fabs(coordinate_marginal_inverse(u, 2) + std::cos(kPi * u)) <= 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Fixed cases
// ---------------------------------------------------------------------------------------------

TEST(CoordinateMarginal, ExtremeAndSpecialU) {
  const double us[] = {1e-300, 1e-200, 1e-100, 1e-30, 1e-16, 0x1p-53, 1e-8, 1e-3, 0.25,
                       std::nextafter(0.25, 1.0), std::nextafter(0.5, 0.0), 0.5,
                       std::nextafter(0.5, 1.0), 0.75, 1.0 - 1e-8, 1.0 - 0x1p-52, 1.0 - 0x1p-53};
  for (const int d : kDims) {
    for (const double u : us) {
      const auto solved = coordinate_marginal_inverse_detail(u, d);
      const Bracket b = bracket_of(u, d, solved.x);
      EXPECT_LE(b.below, b.p + b.tol) << "d=" << d << " u=" << u << " x=" << solved.x;
      EXPECT_GE(b.above, b.p - b.tol) << "d=" << d << " u=" << u << " x=" << solved.x;
      EXPECT_LE(solved.iterations, 40) << "d=" << d << " u=" << u;
    }
  }
  // u = 1/2 is the median, +0.
  for (const int d : kDims) EXPECT_EQ(bits_of(coordinate_marginal_inverse(0.5, d)), 0u);
  // Far tails of small d round to -1 / +1 (the root is within an ulp of them).
  EXPECT_EQ(coordinate_marginal_inverse(1e-300, 2), -1.0);
  EXPECT_EQ(coordinate_marginal_inverse(1e-300, 10), -1.0);
  EXPECT_EQ(coordinate_marginal_inverse(1.0 - 0x1p-53, 2), 1.0);
  // Subnormal u: GSL's tail mass underflows, but the solver still ends (not asserted for
  // accuracy; documented).
  EXPECT_NO_THROW(coordinate_marginal_inverse(std::numeric_limits<double>::denorm_min(), 1000));
}

// Roots computed with mpmath 1.3 at 60 digits (bisection on ln y for
// I_y((d-1)/2, 1/2) = 2u, x = -sqrt(1 - y)), for the exact double values of u.
struct Reference {
  int d;
  double u;
  double x;
};
constexpr Reference kReferences[] = {
    {4, 1e-300, -1.0},
    {4, 1e-100, -1.0},
    {4, 1e-20, -0.9999999999999347674896016},
    {4, 1e-10, -0.9999996972174989787114501},
    {4, 1e-3, -0.9859262426526358208344207},
    {4, 0.05, -0.805383636520119781531461},
    {4, 0.2, -0.4918618327637099057179291},
    {4, 0.3, -0.3196915097905038907832951},
    {4, 0.45, -0.0786208874182278869196862},
    {4, 0.4999999, -0.0000001570796326840072371068908},
    {10, 1e-300, -1.0},
    {10, 1e-100, -0.9999999999999999999999528},
    {10, 1e-20, -0.9999716913954213340888793},
    {10, 1e-10, -0.9952707653959254387717454},
    {10, 1e-3, -0.8199273422597874912270489},
    {10, 0.05, -0.5214043647428331098995185},
    {10, 0.2, -0.2824755943403789992969575},
    {10, 0.3, -0.1782585628722068652002834},
    {10, 0.45, -0.04304437850748396151088798},
    {10, 0.4999999, -8.590292412406684408647775e-8},
    {100, 1e-300, -0.9999995359053628743832867},
    {100, 1e-100, -0.9948940490830505801345267},
    {100, 1e-20, -0.7624423382405953073240087},
    {100, 1e-10, -0.580386890341259254251813},
    {100, 1e-3, -0.3039630105208062998594005},
    {100, 0.05, -0.1645994880618224774555823},
    {100, 0.2, -0.08464763408361562444018528},
    {100, 0.3, -0.05280060435322376925967873},
    {100, 0.45, -0.01266086498624161658831367},
    {100, 0.4999999, -2.525625893813812778766913e-8},
    {1000, 1e-300, -0.8643070698869380114097385},
    {1000, 1e-100, -0.6036793404380011662716159},
    {1000, 1e-20, -0.2869353654412064698549039},
    {1000, 1e-10, -0.1992915557632501251922878},
    {1000, 1e-3, -0.09756171429000263428829553},
    {1000, 0.05, -0.05201864615266130332630996},
    {1000, 0.2, -0.02662965862804089150103803},
    {1000, 0.3, -0.01659430781866422877350236},
    {1000, 0.45, -0.003976728403543243567714453},
    {1000, 0.4999999, -7.932605785594284791991922e-9},
};

TEST(CoordinateMarginal, MatchesHighPrecisionRoots) {
  double worst = 0.0;
  for (const Reference& r : kReferences) {
    const double x = coordinate_marginal_inverse(r.u, r.d);
    const double rel = std::fabs(x - r.x) / std::fabs(r.x);
    worst = std::max(worst, rel);
    EXPECT_LE(rel, 1e-14) << "d=" << r.d << " u=" << r.u << " x=" << x << " ref=" << r.x;
    // Upper tail by symmetry (1 - u is exact for these u only when u >= 1/4; compare
    // against the mirrored root wherever it is).
    if (1.0 - (1.0 - r.u) == r.u) {
      EXPECT_EQ(coordinate_marginal_inverse(1.0 - r.u, r.d), -x);
    }
  }
  std::printf("[ coordinate_marginal ] worst relative error vs mpmath roots: %.2e\n", worst);
}

// d = 5: f = 3/4 (1 - x^2), lower tail F(-t) = (1 - t)^2 (2 + t) / 4 (no cancellation).
double cdf5_lower(double t) {
  const long double a = 1.0L - static_cast<long double>(t);
  return static_cast<double>(a * a * (2.0L + static_cast<long double>(t)) / 4.0L);
}

TEST(CoordinateMarginal, Dimension5ClosedForm) {
  // The CDF itself, lower tail, relative.
  for (int k = 0; k <= 2000; ++k) {
    const double t = k < 1000 ? k / 1000.0 : 1.0 - std::ldexp(1.0, -(k - 1000) / 20 - 1);
    const double ref = cdf5_lower(t);
    if (ref <= 0.0) continue;
    EXPECT_LE(std::fabs(coordinate_marginal_cdf(-t, 5) - ref), 1e-13 * ref) << "t=" << t;
    EXPECT_LE(std::fabs(coordinate_marginal_cdf(t, 5) - (1.0 - ref)), 2.0 * kEps) << "t=" << t;
  }
  // The inverse against the closed form: the true root lies within one ulp of x.
  const double us[] = {1e-300, 1e-100, 1e-20, 1e-8, 1e-3, 0.01, 0.1, 0.2, 0.25, 0.3, 0.4,
                       0.49, 0.4999999};
  for (const double u : us) {
    const double t = -coordinate_marginal_inverse(u, 5);
    const double below = cdf5_lower(std::nextafter(t, 2.0) > 1.0 ? 1.0 : std::nextafter(t, 2.0));
    const double above = cdf5_lower(std::nextafter(t, -1.0));
    EXPECT_LE(below, u * (1.0 + 1e-13)) << "u=" << u << " x=" << -t;
    EXPECT_GE(above, u * (1.0 - 1e-13)) << "u=" << u << " x=" << -t;
  }
}

TEST(CoordinateMarginal, Dimension3IsExactlyLinear) {
  for (int k = 1; k < 4096; ++k) {
    const double u = k / 4096.0;
    EXPECT_EQ(coordinate_marginal_inverse(u, 3), 2.0 * u - 1.0) << "u=" << u;  // exact grid
    EXPECT_EQ(coordinate_marginal_cdf(2.0 * u - 1.0, 3), u);
  }
}

TEST(CoordinateMarginal, Dimension2IsArcsineOnAGrid) {
  for (int k = 1; k < 4096; ++k) {
    const double u = k / 4096.0;
    EXPECT_NEAR(coordinate_marginal_inverse(u, 2), -std::cos(kPi * u), 1e-12) << "u=" << u;
    // and F_2(x) = 1/2 + asin(x) / pi
    const double x = -1.0 + 2.0 * u;
    EXPECT_NEAR(coordinate_marginal_cdf(x, 2), 0.5 + std::asin(x) / kPi, 1e-15) << "x=" << x;
  }
}

// Integrals over x in [a, b] of the pdf, by x = sin(theta): the integrand f(sin th) cos th
// is proportional to cos^(d-2) th, bounded even for d = 2. Composite Simpson with
// 2 * 10^4 panels over at most pi: error below 1e-10 up to d = 1000 (width ~ 1/sqrt(d)).
double integral_of_pdf(double a, double b, int d) {
  const int n = 20000;
  const double lo = std::asin(a), hi = std::asin(b);
  const double h = (hi - lo) / n;
  const auto g = [d](double th) {
    const double s = std::sin(th);
    const double c = std::cos(th);
    if (std::fabs(s) >= 1.0) return d == 2 ? 1.0 / kPi : 0.0;  // the limit at the poles
    return coordinate_marginal_pdf(s, d) * c;
  };
  double sum = g(lo) + g(hi);
  for (int i = 1; i < n; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * g(lo + i * h);
  return sum * h / 3.0;
}

TEST(CoordinateMarginal, PdfIntegratesToOneAndMatchesCdf) {
  for (const int d : kDims) {
    EXPECT_NEAR(integral_of_pdf(-1.0, 1.0, d), 1.0, 1e-10) << "d=" << d;
    const double w = 1.0 / std::sqrt(static_cast<double>(d));
    const double cuts[] = {-1.0, -0.9, std::max(-1.0, -3.0 * w), -w, 0.0, 0.5 * w,
                           std::min(1.0, 2.0 * w), 0.7, 1.0};
    for (const double a : cuts) {
      for (const double b : cuts) {
        if (!(a < b)) continue;
        const double exact = coordinate_marginal_cdf(b, d) - coordinate_marginal_cdf(a, d);
        EXPECT_NEAR(integral_of_pdf(a, b, d), exact, 1e-10) << "d=" << d << " [" << a << ", " << b << "]";
      }
    }
  }
}

TEST(CoordinateMarginal, CdfAndPdfBasics) {
  for (const int d : kDims) {
    EXPECT_EQ(coordinate_marginal_cdf(-1.0, d), 0.0);
    EXPECT_EQ(coordinate_marginal_cdf(-2.0, d), 0.0);
    EXPECT_EQ(coordinate_marginal_cdf(1.0, d), 1.0);
    EXPECT_EQ(coordinate_marginal_cdf(3.0, d), 1.0);
    EXPECT_EQ(coordinate_marginal_cdf(0.0, d), 0.5);
    EXPECT_EQ(coordinate_marginal_pdf(1.5, d), 0.0);
    EXPECT_EQ(coordinate_marginal_pdf(-1.5, d), 0.0);
    EXPECT_TRUE(std::isnan(coordinate_marginal_cdf(std::nan(""), d)));
    EXPECT_TRUE(std::isnan(coordinate_marginal_pdf(std::nan(""), d)));
    for (int k = -99; k <= 99; ++k) {
      const double x = k / 100.0;
      EXPECT_NEAR(coordinate_marginal_cdf(x, d) + coordinate_marginal_cdf(-x, d), 1.0, 4.0 * kEps);
      EXPECT_EQ(coordinate_marginal_pdf(x, d), coordinate_marginal_pdf(-x, d));
    }
  }
  EXPECT_EQ(coordinate_marginal_pdf(1.0, 2), std::numeric_limits<double>::infinity());
  EXPECT_EQ(coordinate_marginal_pdf(1.0, 3), 0.5);
  EXPECT_EQ(coordinate_marginal_pdf(1.0, 4), 0.0);
  EXPECT_NEAR(coordinate_marginal_pdf(0.0, 2), 1.0 / kPi, 4.0 * kEps / kPi);
  EXPECT_NEAR(coordinate_marginal_pdf(0.3, 5), 0.75 * (1.0 - 0.09), 1e-15);
}

// The sampler's own arithmetic uses the portable log, log1p and exp (core/pmath.hpp), so it
// is the same on every CPU and libm: the density is bit for bit the portable formula
// exp((d-3)/2 ln(1 - x^2) - ln B(1/2, (d-1)/2)), with ln(1 - x^2) = log1p(-x^2) below
// x^2 = 1/2 and log((1 - x)(1 + x)) above (GSL's ln B, the documented library part). The
// ctest reference.coordinate_sampler_calls_no_libm checks its object file for libm calls.
TEST(CoordinateMarginal, PdfIsThePortableFormulaBitForBit) {
  namespace pm = axg::core::pm;
  std::size_t compared = 0;
  for (const int d : {2, 4, 5, 7, 10, 50, 100, 1000}) {
    const double ln_beta = gsl_sf_lnbeta(0.5, 0.5 * (d - 1.0));
    for (int k = 0; k < 20000; ++k) {
      const double x = (k + 0.5) / 20000.0;
      const double s = x * x;
      const double ln_y = s < 0.5 ? pm::log1p(-s) : pm::log((1.0 - x) * (1.0 + x));
      const double want = pm::exp(0.5 * (d - 3.0) * ln_y - ln_beta);
      ASSERT_EQ(bits_of(coordinate_marginal_pdf(x, d)), bits_of(want)) << "d=" << d << " x=" << x;
      ASSERT_EQ(bits_of(coordinate_marginal_pdf(-x, d)), bits_of(want)) << "d=" << d << " x=" << -x;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 160000u);
}

TEST(CoordinateMarginal, InvalidArgumentsThrow) {
  const double bad_u[] = {0.0, 1.0, -1e-300, 1.0 + 0x1p-52, -0.5, 2.0,
                          std::numeric_limits<double>::quiet_NaN(),
                          std::numeric_limits<double>::infinity()};
  for (const double u : bad_u) {
    EXPECT_THROW(coordinate_marginal_inverse(u, 10), std::invalid_argument) << "u=" << u;
  }
  for (const int d : {1, 0, -3}) {
    EXPECT_THROW(coordinate_marginal_inverse(0.3, d), std::invalid_argument) << "d=" << d;
    EXPECT_THROW(coordinate_marginal_cdf(0.3, d), std::invalid_argument) << "d=" << d;
    EXPECT_THROW(coordinate_marginal_pdf(0.3, d), std::invalid_argument) << "d=" << d;
  }
}

TEST(CoordinateMarginal, LargeDimensionsConverge) {
  for (const int d : {2000, 10000, 100000}) {
    for (const double u : {1e-300, 1e-30, 1e-5, 0.1, 0.3, 0.5, 0.7, 0.99, 1.0 - 0x1p-53}) {
      const auto solved = coordinate_marginal_inverse_detail(u, d);
      const Bracket b = bracket_of(u, d, solved.x);
      EXPECT_LE(b.below, b.p + b.tol) << "d=" << d << " u=" << u;
      EXPECT_GE(b.above, b.p - b.tol) << "d=" << d << " u=" << u;
    }
  }
}

// Consecutive doubles: non-decreasing up to the noise of the computed F (2e-14 |x|).
TEST(CoordinateMarginal, NearlyMonotoneOnConsecutiveDoubles) {
  double worst = 0.0;
  for (const int d : kDims) {
    for (const double u0 : {1e-300, 1e-10, 0.01, 0.1, 0.25, 0.4999, 0.5, 0.6, 0.75, 0.9, 0.99999}) {
      double u = std::nextafter(u0, 0.0);
      double prev = coordinate_marginal_inverse(u, d);
      for (int j = 0; j < 64; ++j) {
        u = std::nextafter(u, 1.0);
        const double x = coordinate_marginal_inverse(u, d);
        if (x < prev) worst = std::max(worst, (prev - x) / std::fabs(x));
        EXPECT_GE(x, prev - 2e-14 * std::fabs(x)) << "d=" << d << " u=" << u;
        prev = x;
      }
    }
  }
  std::printf("[ coordinate_marginal ] largest reordering of consecutive u: %.2e relative\n",
              worst);
}

TEST(CoordinateMarginal, IndependentOfThreads) {
  std::vector<double> us;
  for (int k = 1; k < 400; ++k) us.push_back(k / 400.0);
  for (int e = 1; e <= 300; e += 13) us.push_back(std::pow(10.0, -e));
  const auto run = [&us](std::vector<std::uint64_t>& out) {
    out.clear();
    for (const int d : kDims) {
      for (const double u : us) out.push_back(bits_of(coordinate_marginal_inverse(u, d)));
    }
  };
  std::vector<std::uint64_t> serial;
  run(serial);
  std::vector<std::vector<std::uint64_t>> parallel(4);
  std::vector<std::thread> threads;
  for (auto& out : parallel) threads.emplace_back(run, std::ref(out));
  for (auto& th : threads) th.join();
  for (const auto& out : parallel) EXPECT_EQ(out, serial);
}

// Speed and iteration counts (printed, not asserted).
TEST(CoordinateMarginal, Timing) {
  constexpr int kCount = 20000;
  std::vector<double> uniform(kCount), tails(kCount);
  for (int i = 0; i < kCount; ++i) {
    uniform[i] = (i + 0.5) / kCount;
    // Log-uniform: lower tail in [1e-300, 1/2], upper tail 1 - q with q in [2^-53, 1/2].
    const double f = (i + 0.5) / kCount;
    tails[i] = (i % 2 == 0) ? 0.5 * std::pow(2e-300, f) : 1.0 - 0.5 * std::pow(0x1p-52, f);
  }
  std::printf("[ coordinate_marginal ]    d   us/call   mean iter   max iter   (u uniform | "
              "u log-uniform tails)\n");
  for (const int d : {3, 10, 100, 1000}) {
    double us_per_call[2];
    double mean_iter[2];
    int max_iter[2];
    const std::vector<double>* sets[2] = {&uniform, &tails};
    for (int s = 0; s < 2; ++s) {
      long total = 0;
      int most = 0;
      double sink = 0.0;
      const auto start = std::chrono::steady_clock::now();
      for (const double u : *sets[s]) {
        const auto solved = coordinate_marginal_inverse_detail(u, d);
        sink += solved.x;
        total += solved.iterations;
        most = std::max(most, solved.iterations);
      }
      const auto stop = std::chrono::steady_clock::now();
      volatile double keep = sink;
      (void)keep;
      us_per_call[s] = std::chrono::duration<double, std::micro>(stop - start).count() / kCount;
      mean_iter[s] = static_cast<double>(total) / kCount;
      max_iter[s] = most;
    }
    std::printf("[ coordinate_marginal ] %4d   %5.2f | %5.2f   %4.2f | %4.2f   %3d | %3d\n", d,
                us_per_call[0], us_per_call[1], mean_iter[0], mean_iter[1], max_iter[0],
                max_iter[1]);
  }
  std::fflush(stdout);
}

}  // namespace
