// Portable transcendental functions (core/pmath.hpp) against glibc: ulp tables, exact edge
// cases, sincos / sincos_turns consistency, RapidCheck identities and a speed comparison.
// The tables and timings are printed so that they can be copied into the docs.
#include "axonguide/core/pmath.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

namespace {

namespace pm = axg::core::pm;
using axg::core::bits_of;
using axg::core::double_of;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMinSubnormal = std::numeric_limits<double>::denorm_min();
const double kMaxSubnormal = double_of(0x000fffffffffffffull);
constexpr double kPi = 3.141592653589793;  // the double nearest pi

struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double unit() { return static_cast<double>(next() >> 11) * 0x1p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  // Sign and significand random, biased exponent uniform in [min_field, max_field]: every
  // binade equally likely (field 0 gives subnormals).
  double any_exponent(int min_field, int max_field, bool random_sign) {
    const std::uint64_t r = next();
    const auto span = static_cast<std::uint64_t>(max_field - min_field + 1);
    const std::uint64_t field = static_cast<std::uint64_t>(min_field) + (r >> 11) % span;
    const std::uint64_t sign = random_sign ? (r & 1) << 63 : 0;
    return double_of(sign | field << 52 | (next() & 0x000fffffffffffffull));
  }
};

// Position on a line where neighbouring doubles are one apart (+0 and -0 coincide).
std::int64_t ordinal(double x) {
  const std::uint64_t b = bits_of(x);
  const auto magnitude = static_cast<std::int64_t>(b & 0x7fffffffffffffffull);
  return (b >> 63) != 0 ? -magnitude : magnitude;
}

std::uint64_t ulp_distance(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) {
    return std::isnan(a) && std::isnan(b) ? 0 : std::numeric_limits<std::uint64_t>::max();
  }
  const std::int64_t d = ordinal(a) - ordinal(b);
  return static_cast<std::uint64_t>(d < 0 ? -d : d);
}

double ulp_of(double x) {
  const double a = std::fabs(x);
  return std::nextafter(a, kInf) - a;
}

#define EXPECT_BITS_EQ(actual, expected)                                                    \
  do {                                                                                      \
    const double a_ = (actual);                                                             \
    const double e_ = (expected);                                                           \
    EXPECT_EQ(bits_of(a_), bits_of(e_)) << #actual << " = " << a_ << " (" << std::hexfloat \
                                        << a_ << "), expected " << e_ << std::defaultfloat; \
  } while (0)

#define EXPECT_ULP_LE(actual, expected, n)                                               \
  do {                                                                                   \
    const double a_ = (actual);                                                          \
    const double e_ = (expected);                                                        \
    EXPECT_LE(ulp_distance(a_, e_), static_cast<std::uint64_t>(n))                       \
        << #actual << " = " << std::hexfloat << a_ << ", glibc " << e_ << std::defaultfloat; \
  } while (0)

// ---------------------------------------------------------------------------------------------
// 1. ulp tables
// ---------------------------------------------------------------------------------------------

struct Row {
  const char* function;
  const char* range;
  std::uint64_t count = 0;
  std::uint64_t max_ulp = 0;
  std::uint64_t differing = 0;
  double worst_argument = 0.0;
};

template <class Ours, class Glibc, class Draw>
Row measure(const char* function, const char* range, std::uint64_t count, std::uint64_t seed,
            Ours ours, Glibc glibc, Draw draw) {
  SplitMix64 rng{seed};
  Row row{function, range};
  row.count = count;
  for (std::uint64_t i = 0; i < count; ++i) {
    const double x = draw(rng);
    const double a = ours(x);
    const double b = glibc(x);
    if (bits_of(a) == bits_of(b)) continue;
    ++row.differing;
    const std::uint64_t d = ulp_distance(a, b);
    if (d > row.max_ulp) {
      row.max_ulp = d;
      row.worst_argument = x;
    }
  }
  return row;
}

TEST(pmath, UlpTableAgainstGlibc) {
  constexpr std::uint64_t kPerFunction = 10'000'000;
  // Split kPerFunction over a function's ranges.
  auto share = [](int i, int ranges) {
    return kPerFunction * static_cast<std::uint64_t>(i + 1) / static_cast<std::uint64_t>(ranges) -
           kPerFunction * static_cast<std::uint64_t>(i) / static_cast<std::uint64_t>(ranges);
  };
  auto log_ours = [](double x) { return pm::log(x); };
  auto log_glibc = [](double x) { return std::log(x); };
  auto exp_ours = [](double x) { return pm::exp(x); };
  auto exp_glibc = [](double x) { return std::exp(x); };
  auto sin_ours = [](double x) { return pm::sin(x); };
  auto sin_glibc = [](double x) { return std::sin(x); };
  auto cos_ours = [](double x) { return pm::cos(x); };
  auto cos_glibc = [](double x) { return std::cos(x); };

  auto log_small = [](SplitMix64& r) {
    return 1e6 * (static_cast<double>((r.next() >> 11) + 1) * 0x1p-53);  // (0, 1e6]
  };
  auto log_near1 = [](SplitMix64& r) { return r.uniform(0.5, 2.0); };
  auto log_all = [](SplitMix64& r) { return r.any_exponent(0, 2046, false); };
  auto exp_full = [](SplitMix64& r) { return r.uniform(-745.0, 710.0); };
  auto exp_unit = [](SplitMix64& r) { return r.uniform(-1.0, 1.0); };
  auto exp_subnormal = [](SplitMix64& r) { return r.uniform(-745.2, -708.4); };
  auto trig_10 = [](SplitMix64& r) { return r.uniform(-10.0, 10.0); };
  auto trig_1e6 = [](SplitMix64& r) { return r.uniform(-1e6, 1e6); };
  auto trig_huge = [](SplitMix64& r) { return r.any_exponent(1023 + 20, 2046, true); };

  std::vector<Row> rows;
  rows.push_back(measure("log", "(0, 1e6]", share(0, 3), 11, log_ours, log_glibc, log_small));
  rows.push_back(measure("log", "[0.5, 2]", share(1, 3), 12, log_ours, log_glibc, log_near1));
  rows.push_back(measure("log", "all positive finite, every binade incl. subnormal", share(2, 3),
                         13, log_ours, log_glibc, log_all));
  rows.push_back(measure("exp", "[-745, 710]", share(0, 3), 21, exp_ours, exp_glibc, exp_full));
  rows.push_back(measure("exp", "[-1, 1]", share(1, 3), 22, exp_ours, exp_glibc, exp_unit));
  rows.push_back(measure("exp", "[-745.2, -708.4] (subnormal results)", share(2, 3), 23, exp_ours,
                         exp_glibc, exp_subnormal));
  const char* kHuge = "+-[2^20, DBL_MAX], every binade";
  rows.push_back(measure("sin", "[-10, 10]", share(0, 3), 31, sin_ours, sin_glibc, trig_10));
  rows.push_back(measure("sin", "[-1e6, 1e6]", share(1, 3), 32, sin_ours, sin_glibc, trig_1e6));
  rows.push_back(measure("sin", kHuge, share(2, 3), 33, sin_ours, sin_glibc, trig_huge));
  rows.push_back(measure("cos", "[-10, 10]", share(0, 3), 41, cos_ours, cos_glibc, trig_10));
  rows.push_back(measure("cos", "[-1e6, 1e6]", share(1, 3), 42, cos_ours, cos_glibc, trig_1e6));
  rows.push_back(measure("cos", kHuge, share(2, 3), 43, cos_ours, cos_glibc, trig_huge));

  std::printf("\n| function | range | count | max ulp vs glibc | differs from glibc | worst x |\n");
  std::printf("|---|---|---:|---:|---:|---|\n");
  for (const Row& row : rows) {
    std::printf("| %s | %s | %llu | %llu | %.4f %% | %a |\n", row.function, row.range,
                static_cast<unsigned long long>(row.count),
                static_cast<unsigned long long>(row.max_ulp),
                100.0 * static_cast<double>(row.differing) / static_cast<double>(row.count),
                row.worst_argument);
  }
  std::fflush(stdout);
  for (const Row& row : rows) {
    EXPECT_LE(row.max_ulp, 1u) << row.function << " on " << row.range << ", worst x = "
                               << std::hexfloat << row.worst_argument;
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Edge cases
// ---------------------------------------------------------------------------------------------

TEST(pmath, EdgeLog) {
  EXPECT_BITS_EQ(pm::log(0.0), -kInf);
  EXPECT_BITS_EQ(pm::log(-0.0), -kInf);
  EXPECT_BITS_EQ(pm::log(1.0), 0.0);  // +0, not -0
  EXPECT_BITS_EQ(pm::log(kInf), kInf);
  EXPECT_TRUE(std::isnan(pm::log(-1.0)));
  EXPECT_TRUE(std::isnan(pm::log(-kMinSubnormal)));
  EXPECT_TRUE(std::isnan(pm::log(-kInf)));
  EXPECT_TRUE(std::isnan(pm::log(kNaN)));
  // Invalid operations give the one fixed NaN, a NaN argument comes back quieted.
  EXPECT_EQ(bits_of(pm::log(-1.0)), 0x7ff8000000000000ull);
  EXPECT_EQ(bits_of(pm::log(double_of(0x7ff0000000000001ull))), 0x7ff8000000000001ull);
  EXPECT_EQ(bits_of(pm::log(double_of(0xfff8000000000123ull))), 0xfff8000000000123ull);

  // -1074 ln 2, -1022 ln 2 and friends: glibc is correctly rounded here, and so are we.
  for (const double x : {kMinSubnormal, kMaxSubnormal, DBL_MIN, DBL_MAX, 2.0, 0.5, 10.0,
                         std::nextafter(1.0, 2.0), std::nextafter(1.0, 0.0)}) {
    EXPECT_BITS_EQ(pm::log(x), std::log(x));
  }
  EXPECT_BITS_EQ(pm::log(kMinSubnormal), -0x1.74385446d71c3p+9);  // -744.44007192138126...
}

TEST(pmath, EdgeExp) {
  EXPECT_BITS_EQ(pm::exp(0.0), 1.0);
  EXPECT_BITS_EQ(pm::exp(-0.0), 1.0);
  EXPECT_BITS_EQ(pm::exp(kInf), kInf);
  EXPECT_BITS_EQ(pm::exp(-kInf), 0.0);
  EXPECT_TRUE(std::isnan(pm::exp(kNaN)));
  EXPECT_EQ(bits_of(pm::exp(double_of(0x7ff0000000000001ull))), 0x7ff8000000000001ull);
  // fdlibm's exp(1) is 1 ulp above the correctly rounded e = 0x1.5bf0a8b145769p+1 (within its
  // < 1 ulp guarantee). Pinned, so that any change to the algorithm shows up here.
  EXPECT_BITS_EQ(pm::exp(1.0), 0x1.5bf0a8b14576ap+1);
  EXPECT_ULP_LE(pm::exp(1.0), 2.718281828459045, 1);
  EXPECT_BITS_EQ(pm::exp(kMinSubnormal), 1.0);

  // Overflow: 709.78271289338397 is the last argument with a finite result.
  const double last_finite = 0x1.62e42fefa39efp+9;
  EXPECT_EQ(pm::exp(last_finite), std::exp(last_finite));
  EXPECT_TRUE(std::isfinite(pm::exp(last_finite)));
  EXPECT_BITS_EQ(pm::exp(std::nextafter(last_finite, kInf)), kInf);
  EXPECT_BITS_EQ(pm::exp(1000.0), kInf);
  EXPECT_BITS_EQ(pm::exp(DBL_MAX), kInf);

  // Underflow: -745.13321910194111 is the last argument with a non-zero (subnormal) result.
  const double last_nonzero = -0x1.74910d52d3051p+9;
  EXPECT_BITS_EQ(pm::exp(last_nonzero), kMinSubnormal);
  EXPECT_BITS_EQ(pm::exp(std::nextafter(last_nonzero, -kInf)), 0.0);
  EXPECT_BITS_EQ(pm::exp(-1000.0), 0.0);
  EXPECT_BITS_EQ(pm::exp(-DBL_MAX), 0.0);
  // The normal / subnormal boundary, ln(DBL_MIN) = -708.39641853226410...
  for (const double x : {-708.3964185322641, -708.0, -709.0, -720.0, -740.0, -744.0}) {
    EXPECT_ULP_LE(pm::exp(x), std::exp(x), 1);
  }
}

// log1p (the coordinate sampler's ln(1 - x^2) = log1p(-x^2) for x^2 < 1/2): its own table, 10^6
// arguments per range, within 1 ulp of glibc everywhere.
TEST(pmath, Log1pAgainstGlibc) {
  auto ours = [](double x) { return pm::log1p(x); };
  auto glibc = [](double x) { return std::log1p(x); };
  std::vector<Row> rows;
  rows.push_back(measure("log1p", "[-0.5, 0] (the coordinate sampler's range)", 1'000'000, 51, ours, glibc,
                         [](SplitMix64& r) { return -0.5 * r.unit(); }));
  rows.push_back(measure("log1p", "(-1, 1]", 1'000'000, 52, ours, glibc, [](SplitMix64& r) {
    return 1.0 - 2.0 * (static_cast<double>((r.next() >> 11) + 1) * 0x1p-53);  // [-1 + 2^-52, 1)
  }));
  rows.push_back(measure("log1p", "+-[2^-60, 2^-10], every binade", 1'000'000, 53, ours, glibc,
                         [](SplitMix64& r) { return r.any_exponent(1023 - 60, 1023 - 10, true); }));
  rows.push_back(measure("log1p", "-1 + [2^-52, 2^-2], every binade", 1'000'000, 54, ours, glibc,
                         [](SplitMix64& r) { return -1.0 + r.any_exponent(1023 - 52, 1023 - 2, false); }));
  rows.push_back(measure("log1p", "(0, 1e6]", 1'000'000, 55, ours, glibc,
                         [](SplitMix64& r) { return 1e6 * (static_cast<double>((r.next() >> 11) + 1) * 0x1p-53); }));
  rows.push_back(measure("log1p", "all positive finite, every binade incl. subnormal", 1'000'000, 56, ours, glibc,
                         [](SplitMix64& r) { return r.any_exponent(0, 2046, false); }));
  std::printf("\n| function | range | count | max ulp vs glibc | differs from glibc | worst x |\n");
  std::printf("|---|---|---:|---:|---:|---|\n");
  for (const Row& row : rows)
    std::printf("| %s | %s | %llu | %llu | %.4f %% | %a |\n", row.function, row.range,
                static_cast<unsigned long long>(row.count), static_cast<unsigned long long>(row.max_ulp),
                100.0 * static_cast<double>(row.differing) / static_cast<double>(row.count), row.worst_argument);
  std::fflush(stdout);
  for (const Row& row : rows)
    EXPECT_LE(row.max_ulp, 1u) << row.function << " on " << row.range << ", worst x = " << std::hexfloat
                               << row.worst_argument;
}

TEST(pmath, EdgeLog1p) {
  EXPECT_BITS_EQ(pm::log1p(0.0), 0.0);
  EXPECT_BITS_EQ(pm::log1p(-0.0), -0.0);
  EXPECT_BITS_EQ(pm::log1p(-1.0), -kInf);
  EXPECT_BITS_EQ(pm::log1p(kInf), kInf);
  EXPECT_EQ(bits_of(pm::log1p(std::nextafter(-1.0, -2.0))), 0x7ff8000000000000ull);
  EXPECT_EQ(bits_of(pm::log1p(-2.0)), 0x7ff8000000000000ull);
  EXPECT_EQ(bits_of(pm::log1p(-kInf)), 0x7ff8000000000000ull);
  EXPECT_EQ(bits_of(pm::log1p(double_of(0x7ff0000000000001ull))), 0x7ff8000000000001ull);
  EXPECT_EQ(bits_of(pm::log1p(double_of(0xfff8000000000123ull))), 0xfff8000000000123ull);
  // Tiny arguments: log1p(x) rounds to x below 2^-54, and keeps the sign of zero.
  for (const double x : {kMinSubnormal, -kMinSubnormal, kMaxSubnormal, DBL_MIN, -DBL_MIN, 0x1p-55, -0x1p-55})
    EXPECT_BITS_EQ(pm::log1p(x), x);
  // Where glibc is correctly rounded, so are we; ln 2 exactly rounded.
  EXPECT_BITS_EQ(pm::log1p(1.0), 0x1.62e42fefa39efp-1);
  for (const double x : {DBL_MAX, 1e300, 0x1p53, 0x1p-29, -0x1p-29, 0x1p-20, -0.5, -0.25, 0.5, 1e-5, -1e-5,
                         std::nextafter(-1.0, 0.0), -0.2928932188134524, 0.41421356237309503})
    EXPECT_ULP_LE(pm::log1p(x), std::log1p(x), 1);
  // log1p(x) and log(1 + x) where 1 + x is exact.
  for (const double x : {1.0, 3.0, -0.5, -0.75, 0.25, 1023.0})
    EXPECT_ULP_LE(pm::log1p(x), pm::log(1.0 + x), 1);
}

TEST(pmath, EdgeSinCosSpecialValues) {
  EXPECT_BITS_EQ(pm::sin(0.0), 0.0);
  EXPECT_BITS_EQ(pm::sin(-0.0), -0.0);  // sign bit kept
  EXPECT_BITS_EQ(pm::cos(0.0), 1.0);
  EXPECT_BITS_EQ(pm::cos(-0.0), 1.0);
  for (const double x : {kMinSubnormal, kMaxSubnormal, DBL_MIN, 1e-10, 0x1p-27}) {
    EXPECT_BITS_EQ(pm::sin(x), x);
    EXPECT_BITS_EQ(pm::sin(-x), -x);
    EXPECT_BITS_EQ(pm::cos(x), 1.0);
    EXPECT_BITS_EQ(pm::cos(-x), 1.0);
  }
  for (const double x : {kInf, -kInf, kNaN}) {
    EXPECT_TRUE(std::isnan(pm::sin(x)));
    EXPECT_TRUE(std::isnan(pm::cos(x)));
  }
  EXPECT_EQ(bits_of(pm::sin(kInf)), 0x7ff8000000000000ull);
  EXPECT_EQ(bits_of(pm::cos(-kInf)), 0x7ff8000000000000ull);
  EXPECT_EQ(bits_of(pm::sin(double_of(0x7ff0000000000001ull))), 0x7ff8000000000001ull);

  EXPECT_BITS_EQ(pm::sin(kPi), 0x1.1a62633145c07p-53);  // pi - fl(pi)
  EXPECT_BITS_EQ(pm::cos(kPi), -1.0);
  EXPECT_BITS_EQ(pm::sin(kPi / 2), 1.0);
  EXPECT_BITS_EQ(pm::cos(kPi / 2), 0x1.1a62633145c07p-54);
  EXPECT_BITS_EQ(pm::sin(2 * kPi), -0x1.1a62633145c07p-52);
  EXPECT_BITS_EQ(pm::cos(2 * kPi), 1.0);
  // sin(1e22) = -0.8522008497671888017727..., cos(1e22) = 0.5232147853951389454975...:
  // sin is correctly rounded, cos 1 ulp above (0x1.0be2cef01c8f3p-1 would be nearest).
  EXPECT_BITS_EQ(pm::sin(1e22), -0.8522008497671888);
  EXPECT_BITS_EQ(pm::cos(1e22), 0x1.0be2cef01c8f4p-1);
  EXPECT_ULP_LE(pm::cos(1e22), 0.5232147853951389, 1);
}

TEST(pmath, EdgeSinCosNearMultiplesOfHalfPi) {
  // The doubles nearest k pi/2 (and their neighbours): the reduced argument cancels down to
  // the rounding error of x, the hardest case for the reduction.
  for (int k = 1; k <= 2000; ++k) {
    const double x = static_cast<double>(k) * (kPi / 2);
    for (const double y : {x, std::nextafter(x, 0.0), std::nextafter(x, kInf), -x}) {
      EXPECT_ULP_LE(pm::sin(y), std::sin(y), 1);
      EXPECT_ULP_LE(pm::cos(y), std::cos(y), 1);
    }
  }
  // Far: multiples of pi/2 around 2^20 (the medium/huge boundary), 1e9, 1e15.
  for (const double base : {0x1p20, 1e9, 1e15}) {
    const double k0 = std::floor(base / (kPi / 2));
    for (int i = 0; i < 200; ++i) {
      const double x = (k0 + i) * (kPi / 2);
      EXPECT_ULP_LE(pm::sin(x), std::sin(x), 1);
      EXPECT_ULP_LE(pm::cos(x), std::cos(x), 1);
    }
  }
  // Kahan & McDonald: 6381956970095103 * 2^797 is the double closest to a multiple of pi/2.
  const double hardest = 6381956970095103.0 * 0x1p797;
  EXPECT_ULP_LE(pm::sin(hardest), std::sin(hardest), 1);
  EXPECT_ULP_LE(pm::cos(hardest), std::cos(hardest), 1);
  EXPECT_LT(std::fabs(pm::cos(hardest)), 1e-18);
}

TEST(pmath, EdgeSinCosHugeArguments) {
  for (const double x : {1e22, 1e100, 1e300, 0x1p1023, DBL_MAX, 0x1.921fb54442d18p+1000,
                         std::nextafter(0x1.921fb54442d18p+20, 0.0), 0x1.921fb54442d18p+20}) {
    EXPECT_ULP_LE(pm::sin(x), std::sin(x), 1);
    EXPECT_ULP_LE(pm::cos(x), std::cos(x), 1);
    EXPECT_ULP_LE(pm::sin(-x), std::sin(-x), 1);
    EXPECT_ULP_LE(pm::cos(-x), std::cos(-x), 1);
  }
}

// ---------------------------------------------------------------------------------------------
// 3. sincos and sincos_turns
// ---------------------------------------------------------------------------------------------

TEST(pmath, SincosSameBitsAsSinAndCos) {
  SplitMix64 rng{5};
  for (int i = 0; i < 1'000'000; ++i) {
    double x = 0.0;
    switch (i % 4) {
      case 0: x = rng.uniform(-1.0, 1.0); break;
      case 1: x = rng.uniform(-1e3, 1e3); break;
      case 2: x = rng.any_exponent(0, 2046, true); break;  // everything, tiny to huge
      default: x = rng.any_exponent(1023 - 30, 1023 + 2, true); break;  // around pi/4
    }
    double s = 0.0;
    double c = 0.0;
    pm::sincos(x, &s, &c);
    ASSERT_EQ(bits_of(s), bits_of(pm::sin(x))) << std::hexfloat << x;
    ASSERT_EQ(bits_of(c), bits_of(pm::cos(x))) << std::hexfloat << x;
  }
  for (const double x : {0.0, -0.0, kMinSubnormal, kInf, -kInf, kNaN, DBL_MAX, kPi / 2}) {
    double s = 0.0;
    double c = 0.0;
    pm::sincos(x, &s, &c);
    EXPECT_EQ(bits_of(s), bits_of(pm::sin(x)));
    EXPECT_EQ(bits_of(c), bits_of(pm::cos(x)));
  }
}

TEST(pmath, SincosTurnsExactQuarterTurns) {
  const struct {
    double u, s, c;
  } cases[] = {{0.0, 0.0, 1.0}, {0.25, 1.0, 0.0}, {0.5, 0.0, -1.0}, {0.75, -1.0, 0.0}};
  for (const auto& k : cases) {
    double s = -1.0;
    double c = -1.0;
    pm::sincos_turns(k.u, &s, &c);
    EXPECT_BITS_EQ(s, k.s);  // zeros are +0
    EXPECT_BITS_EQ(c, k.c);
  }
  double s = 0.0;
  double c = 0.0;
  pm::sincos_turns(0.125, &s, &c);  // pi/4: both sqrt(1/2) = 0.70710678118654752...
  EXPECT_ULP_LE(s, 0x1.6a09e667f3bcdp-1, 1);
  EXPECT_ULP_LE(c, 0x1.6a09e667f3bcdp-1, 1);
  pm::sincos_turns(kMinSubnormal, &s, &c);
  EXPECT_GE(s, 0.0);
  EXPECT_BITS_EQ(c, 1.0);
}

TEST(pmath, SincosTurnsAgainstGlibcAndExtendedPrecision) {
  constexpr long double kTwoPiL = 6.283185307179586476925286766559005768L;
  const double two_pi = 2.0 * kPi;
  SplitMix64 rng{7};
  std::uint64_t max_ulp_ext = 0;
  double worst_tol_glibc = 0.0;  // largest |difference| / (allowed difference) vs glibc
  std::uint64_t differ_glibc = 0;
  constexpr int kCount = 1'000'000;
  for (int i = 0; i < kCount; ++i) {
    // Uniform on the 2^-53 grid, or with a random exponent down to tiny fractions of a turn.
    const double u = (i % 2 == 0) ? rng.unit() : rng.any_exponent(1023 - 60, 1022, false);
    double s = 0.0;
    double c = 0.0;
    pm::sincos_turns(u, &s, &c);

    // Against sin/cos of the exact angle, in 64-bit long double: within 1 ulp, plus the
    // 2^-62-ish error of the long double angle itself where the result is tiny.
    const long double angle = kTwoPiL * static_cast<long double>(u);
    const double se = static_cast<double>(std::sin(angle));
    const double ce = static_cast<double>(std::cos(angle));
    for (const auto& [ours, ref] : {std::pair{s, se}, std::pair{c, ce}}) {
      const double err = std::fabs(ours - ref);
      if (err > 1e-18) {
        const std::uint64_t d = ulp_distance(ours, ref);
        if (d > max_ulp_ext) max_ulp_ext = d;
      }
      ASSERT_LE(err, ulp_of(ref) + 1e-18) << "u = " << std::hexfloat << u;
    }

    // Against glibc on the rounded angle 2 pi u: that angle is off by up to ~1.14e-15 u (the
    // rounding of 2 pi and of the product), so allow our 1 ulp + glibc's 1/2 ulp + that much.
    const double sg = std::sin(two_pi * u);
    const double cg = std::cos(two_pi * u);
    const double arg_tol = 1.2e-15 * u;
    for (const auto& [ours, ref] : {std::pair{s, sg}, std::pair{c, cg}}) {
      if (bits_of(ours) != bits_of(ref)) ++differ_glibc;
      const double allowed = 1.5 * ulp_of(ref) + arg_tol;
      const double ratio = std::fabs(ours - ref) / allowed;
      if (ratio > worst_tol_glibc) worst_tol_glibc = ratio;
      ASSERT_LE(std::fabs(ours - ref), allowed) << "u = " << std::hexfloat << u;
    }

    // Unit circle: s^2 + c^2 within 4 ulp of 1.
    ASSERT_LE(std::fabs(s * s + c * c - 1.0), 4 * DBL_EPSILON) << "u = " << std::hexfloat << u;
  }
  std::printf("sincos_turns: %d arguments; max ulp vs long-double sin/cos(2 pi u) = %llu "
              "(ignoring |diff| <= 1e-18); vs glibc sin/cos(2*pi*u): %.2f %% differ, worst "
              "|diff| = %.3f of the allowance (1.5 ulp + 1.2e-15 u)\n",
              kCount, static_cast<unsigned long long>(max_ulp_ext),
              100.0 * static_cast<double>(differ_glibc) / (2.0 * kCount), worst_tol_glibc);
  std::fflush(stdout);
}

// ---------------------------------------------------------------------------------------------
// 4. Properties
// ---------------------------------------------------------------------------------------------

// Doubles with every binade equally likely: biased exponent in [min_field, max_field].
rc::Gen<double> binade_uniform(int min_field, int max_field, bool random_sign) {
  return rc::gen::resize(
      rc::kNominalSize,
      rc::gen::apply(
          [random_sign](int field, std::uint64_t significand, bool negative) {
            const std::uint64_t sign = random_sign && negative ? 1ull << 63 : 0;
            return double_of(sign | static_cast<std::uint64_t>(field) << 52 | significand);
          },
          rc::gen::inRange(min_field, max_field + 1),
          rc::gen::inRange<std::uint64_t>(0, 1ull << 52), rc::gen::arbitrary<bool>()));
}

// exp(log x) = x up to the rounding of log x, which exp turns into a relative error of
// |log x| ulp-of-1: so the bound is (|log x| + 2) * 2^-52 relative, a few ulps only near x = 1.
RC_GTEST_PROP(pmath, PropertyExpOfLogIsIdentity, ()) {
  const double x = *binade_uniform(1, 2046, false);
  const double y = pm::exp(pm::log(x));
  const double bound = (std::fabs(std::log(x)) + 2.0) * DBL_EPSILON * x;
  RC_ASSERT(std::fabs(y - x) <= bound);
}

RC_GTEST_PROP(pmath, PropertyExpOfLogNearOneIsWithinFewUlps, ()) {
  const double x = *binade_uniform(1023 - 4, 1023 + 3, false);  // [1/16, 16)
  RC_ASSERT(ulp_distance(pm::exp(pm::log(x)), x) <= 4u);
}

RC_GTEST_PROP(pmath, PropertySinSquaredPlusCosSquaredIsOne, ()) {
  const double x = *binade_uniform(0, 2046, true);
  const double s = pm::sin(x);
  const double c = pm::cos(x);
  RC_ASSERT(std::fabs(s * s + c * c - 1.0) <= 1e-15);
}

RC_GTEST_PROP(pmath, PropertySinIsOddCosIsEven, ()) {
  const double x = *binade_uniform(0, 2046, false);
  RC_ASSERT(bits_of(pm::sin(-x)) == (bits_of(pm::sin(x)) ^ (1ull << 63)));
  RC_ASSERT(bits_of(pm::cos(-x)) == bits_of(pm::cos(x)));
}

// ---------------------------------------------------------------------------------------------
// 5. Speed (printed, not asserted)
// ---------------------------------------------------------------------------------------------

template <class F>
double ns_per_call(const std::vector<double>& args, int repeats, F f) {
  double sink = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (int r = 0; r < repeats; ++r) {
    for (const double x : args) sink += f(x);
  }
  const auto stop = std::chrono::steady_clock::now();
  volatile double keep = sink;
  (void)keep;
  return std::chrono::duration<double, std::nano>(stop - start).count() /
         (static_cast<double>(args.size()) * repeats);
}

TEST(pmath, SpeedNanosecondsPerCall) {
  constexpr std::size_t kArgs = 1 << 16;
  constexpr int kRepeats = 8;
  SplitMix64 rng{99};
  auto fill = [&](auto draw) {
    std::vector<double> v(kArgs);
    for (double& x : v) x = draw();
    return v;
  };
  const auto log_args = fill([&] { return rng.uniform(1e-3, 1e6); });
  const auto exp_args = fill([&] { return rng.uniform(-700.0, 700.0); });
  const auto trig_args = fill([&] { return rng.uniform(-10.0, 10.0); });
  const auto trig_1e6 = fill([&] { return rng.uniform(-1e6, 1e6); });
  const auto trig_huge = fill([&] { return rng.any_exponent(1023 + 20, 2046, true); });
  const auto turns = fill([&] { return rng.unit(); });
  const double two_pi = 2.0 * kPi;

  struct Timing {
    const char* what;
    double ours;
    double glibc;
  };
  const Timing timings[] = {
      {"log (1e-3, 1e6)", ns_per_call(log_args, kRepeats, [](double x) { return pm::log(x); }),
       ns_per_call(log_args, kRepeats, [](double x) { return std::log(x); })},
      {"exp [-700, 700]", ns_per_call(exp_args, kRepeats, [](double x) { return pm::exp(x); }),
       ns_per_call(exp_args, kRepeats, [](double x) { return std::exp(x); })},
      {"sin [-10, 10]", ns_per_call(trig_args, kRepeats, [](double x) { return pm::sin(x); }),
       ns_per_call(trig_args, kRepeats, [](double x) { return std::sin(x); })},
      {"cos [-10, 10]", ns_per_call(trig_args, kRepeats, [](double x) { return pm::cos(x); }),
       ns_per_call(trig_args, kRepeats, [](double x) { return std::cos(x); })},
      {"sin [-1e6, 1e6]", ns_per_call(trig_1e6, kRepeats, [](double x) { return pm::sin(x); }),
       ns_per_call(trig_1e6, kRepeats, [](double x) { return std::sin(x); })},
      {"sin huge (Payne-Hanek)",
       ns_per_call(trig_huge, kRepeats, [](double x) { return pm::sin(x); }),
       ns_per_call(trig_huge, kRepeats, [](double x) { return std::sin(x); })},
      {"sincos [-10, 10] (glibc: sin + cos)",
       ns_per_call(trig_args, kRepeats,
                   [](double x) {
                     double s = 0.0;
                     double c = 0.0;
                     pm::sincos(x, &s, &c);
                     return s + c;
                   }),
       ns_per_call(trig_args, kRepeats, [](double x) { return std::sin(x) + std::cos(x); })},
      {"sincos_turns [0, 1) (glibc: sin + cos of 2 pi u)",
       ns_per_call(turns, kRepeats,
                   [](double u) {
                     double s = 0.0;
                     double c = 0.0;
                     pm::sincos_turns(u, &s, &c);
                     return s + c;
                   }),
       ns_per_call(turns, kRepeats,
                   [two_pi](double u) { return std::sin(two_pi * u) + std::cos(two_pi * u); })},
  };
  std::printf("\n| function | ours ns/call | glibc ns/call |\n|---|---:|---:|\n");
  for (const Timing& t : timings) std::printf("| %s | %.1f | %.1f |\n", t.what, t.ours, t.glibc);
  std::fflush(stdout);
}

}  // namespace
