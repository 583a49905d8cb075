#pragma once
// Portable log, exp, sin, cos: the same bits on the host (x86-64, SSE2, -ffp-contract=off) and
// in CUDA device code (--fmad=false). They use only + - * /, comparisons, integer and bit
// operations, all IEEE-exact or correctly rounded, so no libm and no FMA can change a result.
// Accuracy: below 1 ulp (fdlibm's error analysis); tests/reference/core/pmath_test.cpp measures
// the distance to glibc.
//
// NaN results are bit-exact too: a NaN argument comes back quieted with its payload, and an
// invalid operation (log(-1), sin(inf)) returns the fixed quiet NaN 0x7ff8000000000000 rather
// than whatever NaN the hardware would produce (x86 and NVIDIA differ there).
//
// The algorithms and coefficients are those of fdlibm as kept in FreeBSD msun (e_log.c,
// e_exp.c, k_sin.c, k_cos.c, e_rem_pio2.c, k_rem_pio2.c), rewritten here:
//
// ====================================================
// Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
// Copyright (C) 2004 by Sun Microsystems, Inc. All rights reserved. (e_exp.c)
//
// Developed at SunSoft, a Sun Microsystems, Inc. business.
// Permission to use, copy, modify, and distribute this
// software is freely granted, provided that this notice
// is preserved.
// ====================================================
//
// e_rem_pio2.c: optimized by Bruce D. Evans.
#include <cstdint>

#include "hd.hpp"

namespace axg::core::pm {
namespace detail {

AXG_HDI std::uint32_t high_word(double x) { return static_cast<std::uint32_t>(bits_of(x) >> 32); }

AXG_HDI std::uint32_t low_word(double x) { return static_cast<std::uint32_t>(bits_of(x)); }

AXG_HDI double with_high_word(double x, std::uint32_t high) {
  return double_of((static_cast<std::uint64_t>(high) << 32) | low_word(x));
}

// 2^k, exact, for k in the normal range [-1022, 1023].
AXG_HDI double pow2(int k) { return double_of(static_cast<std::uint64_t>(k + 1023) << 52); }

AXG_HDI bool is_nan(double x) {
  return (bits_of(x) & 0x7fffffffffffffffull) > 0x7ff0000000000000ull;
}

// The NaN argument itself, quieted: x + x would do it on x86 but not reliably on a GPU.
AXG_HDI double quieted(double x) { return double_of(bits_of(x) | 0x0008000000000000ull); }

AXG_HDI double invalid_nan() { return double_of(0x7ff8000000000000ull); }

AXG_HDI double infinity() { return double_of(0x7ff0000000000000ull); }

// sin and cos of a non-finite argument.
AXG_HDI double trig_of_non_finite(double x) { return is_nan(x) ? quieted(x) : invalid_nan(); }

// sin(x + tail) for |x + tail| <~ pi/4, where tail is below half an ulp of x (the second word
// of a reduced argument). Degree-13 odd polynomial, error below 2^-58 relative. Callers return
// x itself for tiny x: the polynomial does not preserve -0.
AXG_HDI double kernel_sin(double x, double tail, bool has_tail) {
  constexpr double S1 = -0x1.5555555555549p-3;
  constexpr double S2 = 0x1.111111110f8a6p-7;
  constexpr double S3 = -0x1.a01a019c161d5p-13;
  constexpr double S4 = 0x1.71de357b1fe7dp-19;
  constexpr double S5 = -0x1.ae5e68a2b9cebp-26;
  constexpr double S6 = 0x1.5d93a5acfd57cp-33;
  const double z = x * x;
  const double w = z * z;
  const double r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
  const double v = z * x;
  if (!has_tail) return x + v * (S1 + z * r);
  // sin(x + t) ~ sin(x) + (1 - x^2/2) t, folded in so that the small terms are added first.
  return x - ((z * (0.5 * tail - v * r) - tail) - v * S1);
}

// cos(x + tail) for |x + tail| <~ pi/4. Degree-14 even polynomial, error below 2^-58.
AXG_HDI double kernel_cos(double x, double tail) {
  constexpr double C1 = 0x1.555555555554cp-5;
  constexpr double C2 = -0x1.6c16c16c15177p-10;
  constexpr double C3 = 0x1.a01a019cb1590p-16;
  constexpr double C4 = -0x1.27e4f809c52adp-22;
  constexpr double C5 = 0x1.1ee9ebdb4b1c4p-29;
  constexpr double C6 = -0x1.8fae9be8838d4p-37;
  const double z = x * x;
  const double w = z * z;
  const double r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
  const double half_z = 0.5 * z;
  const double head = 1.0 - half_z;
  // head + ((1 - head) - half_z) is exactly 1 - z/2; cos(x + t) ~ cos(x) - x t.
  return head + (((1.0 - head) - half_z) + (z * r - x * tail));
}

// Payne-Hanek reduction for huge arguments (fdlibm's __kernel_rem_pio2, double precision only).
// The positive argument is chunk[0] * 2^e0 + chunk[1] * 2^(e0-24) + chunk[2] * 2^(e0-48), each
// chunk a 24-bit integer. Writes y0 + y1 = x - n pi/2 (|y| <= pi/4) and returns n mod 8. Only
// the bits of 2/pi that matter mod 8 are multiplied in, so the cost does not grow with x.
AXG_HDI int rem_pio2_large(const double* chunk, int chunks, int e0, double& y0, double& y1) {
  // Bits of 2/pi after the binary point, 24 per entry: enough for every double.
  const std::int32_t two_over_pi[66] = {
      0xA2F983, 0x6E4E44, 0x1529FC, 0x2757D1, 0xF534DD, 0xC0DB62, 0x95993C, 0x439041, 0xFE5163,
      0xABDEBB, 0xC561B7, 0x246E3A, 0x424DD2, 0xE00649, 0x2EEA09, 0xD1921C, 0xFE1DEB, 0x1CB129,
      0xA73EE8, 0x8235F5, 0x2EBB44, 0x84E99C, 0x7026B4, 0x5F7E41, 0x3991D6, 0x398353, 0x39F49C,
      0x845F8B, 0xBDF928, 0x3B1FF8, 0x97FFDE, 0x05980F, 0xEF2F11, 0x8B5A0A, 0x6D1F6D, 0x367ECF,
      0x27CB09, 0xB74F46, 0x3F669E, 0x5FEA2D, 0x7527BA, 0xC7EBE5, 0xF17B3D, 0x0739F7, 0x8A5292,
      0xEA6BFB, 0x5FB11F, 0x8D5D08, 0x560330, 0x46FC7B, 0x6BABF0, 0xCFBC20, 0x9AF436, 0x1DA9E3,
      0x91615E, 0xE61B08, 0x659985, 0x5F14A0, 0x68408D, 0xFFD880, 0x4D7327, 0x310606, 0x1556CA,
      0x73A8C9, 0x60E27B, 0xC08C6B,
  };
  // pi/2 in 24-bit pieces, so that each product with a 24-bit chunk of the fraction is exact.
  const double pio2_pieces[8] = {
      0x1.921fb40000000p+0,   0x1.4442d00000000p-24,  0x1.8469880000000p-48,
      0x1.8cc5160000000p-72,  0x1.01b8380000000p-96,  0x1.a252040000000p-120,
      0x1.3822280000000p-145, 0x1.9f31d00000000p-169,
  };
  constexpr double two24 = 0x1p24;
  constexpr double two_minus24 = 0x1p-24;
  // Terms of the product computed at first: two more than 53 bits need, so that up to 24 bits
  // of integer part and 23 of cancellation in the fraction can be detected and recomputed.
  constexpr int initial_terms = 4;
  constexpr int last_pio2_piece = initial_terms;

  const int last_chunk = chunks - 1;
  // Skip the leading bits of 2/pi whose product with x is a multiple of 8 (= 0 mod 2 pi).
  int skip = (e0 - 3) / 24;
  if (skip < 0) skip = 0;
  int q0 = e0 - 24 * (skip + 1);  // exponent of the leading product term

  double factor[20];  // the needed 24-bit pieces of 2/pi, as doubles
  double product[20];
  double fraction_terms[20];
  std::int32_t digits[20];  // the product as base-2^24 digits, least significant first
  for (int i = 0, j = skip - last_chunk; i <= last_chunk + initial_terms; ++i, ++j) {
    factor[i] = j < 0 ? 0.0 : static_cast<double>(two_over_pi[j]);
  }
  for (int i = 0; i <= initial_terms; ++i) {
    double sum = 0.0;
    for (int j = 0; j <= last_chunk; ++j) sum += chunk[j] * factor[last_chunk + i - j];
    product[i] = sum;
  }

  int last_term = initial_terms;
  int n = 0;
  int high = 0;  // > 0 when the fraction is >= 1/2 (then we take fraction - 1, and negate)
  double z = 0.0;
  for (;;) {
    // Distill the product terms into 24-bit digits, carrying upwards.
    z = product[last_term];
    for (int i = 0, j = last_term; j > 0; ++i, --j) {
      const double carry = static_cast<double>(static_cast<std::int32_t>(two_minus24 * z));
      digits[i] = static_cast<std::int32_t>(z - two24 * carry);
      z = product[j - 1] + carry;
    }

    // Integer part mod 8, and the fraction.
    z *= pow2(q0);
    z -= 8.0 * static_cast<double>(static_cast<std::int64_t>(z * 0.125));  // z >= 0: trunc = floor
    n = static_cast<std::int32_t>(z);
    z -= static_cast<double>(n);
    high = 0;
    if (q0 > 0) {  // the lowest integer bits sit in the top digit
      const std::int32_t integer_bits = digits[last_term - 1] >> (24 - q0);
      n += integer_bits;
      digits[last_term - 1] -= integer_bits << (24 - q0);
      high = digits[last_term - 1] >> (23 - q0);
    } else if (q0 == 0) {
      high = digits[last_term - 1] >> 23;
    } else if (z >= 0.5) {
      high = 2;
    }

    if (high > 0) {  // fraction >= 1/2: round n up and replace the fraction by 1 - fraction
      n += 1;
      bool borrow = false;
      for (int i = 0; i < last_term; ++i) {
        const std::int32_t d = digits[i];
        if (!borrow) {
          if (d != 0) {
            borrow = true;
            digits[i] = 0x1000000 - d;
          }
        } else {
          digits[i] = 0xffffff - d;
        }
      }
      if (q0 == 1) digits[last_term - 1] &= 0x7fffff;
      if (q0 == 2) digits[last_term - 1] &= 0x3fffff;
      if (high == 2) {
        z = 1.0 - z;
        if (borrow) z -= pow2(q0);
      }
    }

    // If the fraction cancelled down to nothing so far, more bits of 2/pi are needed.
    if (z != 0.0) break;
    std::int32_t any = 0;
    for (int i = last_term - 1; i >= initial_terms; --i) any |= digits[i];
    if (any != 0) break;
    int extra = 1;
    while (digits[initial_terms - extra] == 0) ++extra;
    for (int i = last_term + 1; i <= last_term + extra; ++i) {
      factor[last_chunk + i] = static_cast<double>(two_over_pi[skip + i]);
      double sum = 0.0;
      for (int j = 0; j <= last_chunk; ++j) sum += chunk[j] * factor[last_chunk + i - j];
      product[i] = sum;
    }
    last_term += extra;
  }

  // Drop zero digits at the top, or split the remaining fraction z into digits.
  if (z == 0.0) {
    last_term -= 1;
    q0 -= 24;
    while (digits[last_term] == 0) {
      last_term -= 1;
      q0 -= 24;
    }
  } else {
    z *= pow2(-q0);
    if (z >= two24) {
      const double carry = static_cast<double>(static_cast<std::int32_t>(two_minus24 * z));
      digits[last_term] = static_cast<std::int32_t>(z - two24 * carry);
      last_term += 1;
      q0 += 24;
      digits[last_term] = static_cast<std::int32_t>(carry);
    } else {
      digits[last_term] = static_cast<std::int32_t>(z);
    }
  }

  // Fraction digits back to doubles, then multiply by pi/2 (each term exact or nearly).
  double scale = pow2(q0);
  for (int i = last_term; i >= 0; --i) {
    product[i] = scale * static_cast<double>(digits[i]);
    scale *= two_minus24;
  }
  for (int i = last_term; i >= 0; --i) {
    double sum = 0.0;
    for (int k = 0; k <= last_pio2_piece && k <= last_term - i; ++k) {
      sum += pio2_pieces[k] * product[i + k];
    }
    fraction_terms[last_term - i] = sum;
  }

  // Sum smallest first into a head and a tail.
  double sum = 0.0;
  for (int i = last_term; i >= 0; --i) sum += fraction_terms[i];
  y0 = high == 0 ? sum : -sum;
  sum = fraction_terms[0] - sum;
  for (int i = 1; i <= last_term; ++i) sum += fraction_terms[i];
  y1 = high == 0 ? sum : -sum;
  return n & 7;
}

// |x| < 2^20 pi/2, or x near a small multiple of pi/2: x - n pi/2 with pi/2 in three 33-bit
// pieces, the later ones only used when cancellation has eaten into the first result.
AXG_HDI int rem_pio2_medium(double x, std::uint32_t ix, double& y0, double& y1) {
  constexpr double inv_pio2 = 0x1.45f306dc9c883p-1;
  constexpr double pio2_1 = 0x1.921fb54400000p+0;  // first 33 bits of pi/2
  constexpr double pio2_1t = 0x1.0b4611a626331p-34;  // pi/2 - pio2_1
  constexpr double pio2_2 = 0x1.0b4611a600000p-34;  // second 33 bits
  constexpr double pio2_2t = 0x1.3198a2e037073p-69;  // pi/2 - (pio2_1 + pio2_2)
  constexpr double pio2_3 = 0x1.3198a2e000000p-69;  // third 33 bits
  constexpr double pio2_3t = 0x1.b839a252049c1p-104;  // pi/2 - (pio2_1 + pio2_2 + pio2_3)
  constexpr double round_shift = 0x1.8p52;           // adding it rounds to an integer

  const double fn = (x * inv_pio2 + round_shift) - round_shift;
  const int n = static_cast<std::int32_t>(fn);
  double r = x - fn * pio2_1;  // exact: fn * pio2_1 has at most 53 bits
  double w = fn * pio2_1t;
  const int exponent = static_cast<int>(ix >> 20);
  y0 = r - w;
  int lost = exponent - static_cast<int>((high_word(y0) >> 20) & 0x7ff);
  if (lost > 16) {  // good to 118 bits
    double t = r;
    w = fn * pio2_2;
    r = t - w;
    w = fn * pio2_2t - ((t - r) - w);
    y0 = r - w;
    lost = exponent - static_cast<int>((high_word(y0) >> 20) & 0x7ff);
    if (lost > 49) {  // good to 151 bits, enough for every double
      t = r;
      w = fn * pio2_3;
      r = t - w;
      w = fn * pio2_3t - ((t - r) - w);
      y0 = r - w;
    }
  }
  y1 = (r - y0) - w;
  return n;
}

// x - n pi/2 = y0 + y1 with |y0 + y1| <~ pi/4, for finite |x| > pi/4. Returns n (its low
// bits select the quadrant).
AXG_HDI int rem_pio2(double x, double& y0, double& y1) {
  const std::uint32_t hx = high_word(x);
  const bool negative = (hx >> 31) != 0;
  const std::uint32_t ix = hx & 0x7fffffff;

  // |x| <~ 9pi/4: subtract n pi/2 (n = 1..4) directly, except next to pi/2, pi, 3pi/2, 2pi
  // where the cancellation needs the medium path's extra pieces.
  if (ix <= 0x401c463b) {
    if ((ix & 0xfffff) == 0x921fb || ix == 0x4012d97c) return rem_pio2_medium(x, ix, y0, y1);
    constexpr double pio2_1 = 0x1.921fb54400000p+0;
    constexpr double pio2_1t = 0x1.0b4611a626331p-34;
    const int n = ix <= 0x4002d97c ? 1 : ix <= 0x400f6a7a ? 2 : ix <= 0x4015fdbc ? 3 : 4;
    const double m = n;  // m * pio2_1 is exact; m * pio2_1t rounds as in fdlibm
    if (!negative) {
      const double z = x - m * pio2_1;
      y0 = z - m * pio2_1t;
      y1 = (z - y0) - m * pio2_1t;
      return n;
    }
    const double z = x + m * pio2_1;
    y0 = z + m * pio2_1t;
    y1 = (z - y0) + m * pio2_1t;
    return -n;
  }
  if (ix < 0x413921fb) return rem_pio2_medium(x, ix, y0, y1);  // |x| < 2^20 pi/2

  // Huge: scale |x| to [2^23, 2^24) and cut it into three 24-bit chunks.
  const int e0 = static_cast<int>(ix >> 20) - 1046;  // ilogb(x) - 23
  double z = double_of((static_cast<std::uint64_t>(ix - static_cast<std::uint32_t>(e0 * 0x100000))
                        << 32) |
                       low_word(x));
  double chunk[3];
  for (int i = 0; i < 2; ++i) {
    chunk[i] = static_cast<double>(static_cast<std::int32_t>(z));
    z = (z - chunk[i]) * 0x1p24;
  }
  chunk[2] = z;
  int chunks = 3;
  while (chunk[chunks - 1] == 0.0) --chunks;
  double t0 = 0.0;
  double t1 = 0.0;
  const int n = rem_pio2_large(chunk, chunks, e0, t0, t1);
  if (negative) {
    y0 = -t0;
    y1 = -t1;
    return -n;
  }
  y0 = t0;
  y1 = t1;
  return n;
}

// ln 2 split so that k ln2_hi is exact for |k| < 2000, and the coefficients of fdlibm's
// log(1 + f) = 2s + s R(s^2) (shared by log and log1p; exp uses ln 2 the same way).
inline constexpr double kLn2Hi = 0x1.62e42fee00000p-1;
inline constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;
inline constexpr double kLog1 = 0x1.5555555555593p-1;
inline constexpr double kLog2 = 0x1.999999997fa04p-2;
inline constexpr double kLog3 = 0x1.2492494229359p-2;
inline constexpr double kLog4 = 0x1.c71c51d8e78afp-3;
inline constexpr double kLog5 = 0x1.7466496cb03dep-3;
inline constexpr double kLog6 = 0x1.39a09d078c69fp-3;
inline constexpr double kLog7 = 0x1.2f112df3e5244p-3;

}  // namespace detail

// Natural logarithm. log(+-0) = -inf, log(x < 0) = NaN, log(inf) = inf, log(1) = +0.
// x = 2^k (1 + f) with sqrt(2)/2 < 1 + f < sqrt(2); log(1 + f) = 2s + s R(s^2), s = f / (2 + f).
AXG_HDI double log(double x) {

  if (detail::is_nan(x)) return detail::quieted(x);
  std::int32_t hx = static_cast<std::int32_t>(detail::high_word(x));
  int k = 0;
  if (hx < 0x00100000) {  // zero, negative or subnormal
    if (((hx & 0x7fffffff) | static_cast<std::int32_t>(detail::low_word(x))) == 0) {
      return -detail::infinity();
    }
    if (hx < 0) return detail::invalid_nan();
    k -= 54;
    x *= 0x1p54;  // subnormal: scale into the normal range
    hx = static_cast<std::int32_t>(detail::high_word(x));
  }
  if (hx >= 0x7ff00000) return x;  // +inf
  k += (hx >> 20) - 1023;
  hx &= 0x000fffff;
  // Normalize the significand into [sqrt(2)/2, sqrt(2)): take x/2 above sqrt(2).
  const std::int32_t above_sqrt2 = (hx + 0x95f64) & 0x100000;
  x = detail::with_high_word(x, static_cast<std::uint32_t>(hx | (above_sqrt2 ^ 0x3ff00000)));
  k += above_sqrt2 >> 20;
  const double f = x - 1.0;
  const double dk = k;
  if ((0x000fffff & (2 + hx)) < 3) {  // -2^-20 <= f < 2^-20: a short series suffices
    if (f == 0.0) return k == 0 ? 0.0 : dk * detail::kLn2Hi + dk * detail::kLn2Lo;
    const double R = f * f * (0.5 - 0.33333333333333333 * f);
    return k == 0 ? f - R : dk * detail::kLn2Hi - ((R - dk * detail::kLn2Lo) - f);
  }
  const double s = f / (2.0 + f);
  const double z = s * s;
  const double w = z * z;
  const double t1 = w * (detail::kLog2 + w * (detail::kLog4 + w * detail::kLog6));
  const double t2 = z * (detail::kLog1 + w * (detail::kLog3 + w * (detail::kLog5 + w * detail::kLog7)));
  const double R = t2 + t1;
  // Near the ends of the interval (|f| >~ 0.28: significand of x in [1.38, 1.42]) f - s (f - R)
  // loses too much; splitting out f^2/2 keeps the error below 1 ulp.
  if (((hx - 0x6147a) | (0x6b851 - hx)) > 0) {
    const double half_f2 = 0.5 * f * f;
    if (k == 0) return f - (half_f2 - s * (half_f2 + R));
    return dk * detail::kLn2Hi - ((half_f2 - (s * (half_f2 + R) + dk * detail::kLn2Lo)) - f);
  }
  if (k == 0) return f - s * (f - R);
  return dk * detail::kLn2Hi - ((s * (f - R) - dk * detail::kLn2Lo) - f);
}

// log(1 + x), accurate for small |x| too (fdlibm s_log1p.c). log1p(-1) = -inf, log1p(x < -1)
// = NaN, log1p(+-0) = +-0, log1p(inf) = inf. 1 + x = 2^k (1 + f) with sqrt(2)/2 < 1 + f <
// sqrt(2), and a correction c for the rounding of 1 + x; then the polynomial of log.
AXG_HDI double log1p(double x) {

  if (detail::is_nan(x)) return detail::quieted(x);
  const std::int32_t hx = static_cast<std::int32_t>(detail::high_word(x));
  const std::int32_t ax = hx & 0x7fffffff;
  int k = 1;
  double f = 0.0, c = 0.0;
  std::int32_t hu = 0;
  if (hx < 0x3FDA827A) {       // 1 + x < sqrt(2)+
    if (ax >= 0x3ff00000) {    // x <= -1
      return x == -1.0 ? -detail::infinity() : detail::invalid_nan();
    }
    if (ax < 0x3e200000) {     // |x| < 2^-29
      if (ax < 0x3c900000) return x;  // |x| < 2^-54 (keeps -0)
      return x - x * x * 0.5;
    }
    if (hx > 0 || hx <= static_cast<std::int32_t>(0xbfd2bec4u)) {  // sqrt(2)/2- <= 1 + x < sqrt(2)+
      k = 0;
      f = x;
      hu = 1;
    }
  }
  if (hx >= 0x7ff00000) return x;  // +inf
  if (k != 0) {
    double u;
    if (hx < 0x43400000) {  // x < 2^53: 1 + x is inexact, keep the correction term
      u = 1.0 + x;
      hu = static_cast<std::int32_t>(detail::high_word(u));
      k = (hu >> 20) - 1023;
      c = k > 0 ? 1.0 - (u - x) : x - (u - 1.0);
      c /= u;
    } else {
      u = x;
      hu = static_cast<std::int32_t>(detail::high_word(u));
      k = (hu >> 20) - 1023;
      c = 0.0;
    }
    hu &= 0x000fffff;
    // The thresholds above are looser than this one, so k == 0 is never reached here
    // (which would drop the correction term).
    if (hu < 0x6a09e) {  // u <~ sqrt(2): normalize u
      u = detail::with_high_word(u, static_cast<std::uint32_t>(hu | 0x3ff00000));
    } else {             // normalize u / 2
      k += 1;
      u = detail::with_high_word(u, static_cast<std::uint32_t>(hu | 0x3fe00000));
      hu = (0x00100000 - hu) >> 2;
    }
    f = u - 1.0;
  }
  const double hfsq = 0.5 * f * f;
  const double dk = k;
  if (hu == 0) {  // |f| < 2^-20
    if (f == 0.0) {
      if (k == 0) return 0.0;
      c += dk * detail::kLn2Lo;
      return dk * detail::kLn2Hi + c;
    }
    const double R = hfsq * (1.0 - 0.66666666666666666 * f);
    if (k == 0) return f - R;
    return dk * detail::kLn2Hi - ((R - (dk * detail::kLn2Lo + c)) - f);
  }
  const double s = f / (2.0 + f);
  const double z = s * s;
  using namespace detail;
  const double R = z * (kLog1 + z * (kLog2 + z * (kLog3 + z * (kLog4 + z * (kLog5 + z * (kLog6 + z * kLog7))))));
  if (k == 0) return f - (hfsq - s * (hfsq + R));
  return dk * detail::kLn2Hi - ((hfsq - (s * (hfsq + R) + (dk * detail::kLn2Lo + c))) - f);
}

// e^x. Overflows to +inf above 709.78..., goes through the subnormals to +0 below -745.13...
// x = k ln2 + r with |r| <= ln2/2; e^r = 1 + r + r c(r) / (2 - c(r)) with a rational c.
AXG_HDI double exp(double x) {
  constexpr double overflow_threshold = 0x1.62e42fefa39efp+9;    // 709.78...
  constexpr double underflow_threshold = -0x1.74910d52d3051p+9;  // -745.13...
  constexpr double inv_ln2 = 0x1.71547652b82fep+0;
  constexpr double P1 = 0x1.555555555553ep-3;
  constexpr double P2 = -0x1.6c16c16bebd93p-9;
  constexpr double P3 = 0x1.1566aaf25de2cp-14;
  constexpr double P4 = -0x1.bbd41c5d26bf1p-20;
  constexpr double P5 = 0x1.6376972bea4d0p-25;

  const std::uint32_t hw = detail::high_word(x);
  const bool negative = (hw >> 31) != 0;
  const std::uint32_t hx = hw & 0x7fffffff;
  if (hx >= 0x40862E42) {  // |x| >= 709.78...
    if (hx >= 0x7ff00000) {
      if (detail::is_nan(x)) return detail::quieted(x);
      return negative ? 0.0 : x;  // e^-inf = 0, e^inf = inf
    }
    if (x > overflow_threshold) return detail::infinity();
    if (x < underflow_threshold) return 0.0;
  }

  double hi = 0.0;
  double lo = 0.0;
  int k = 0;
  if (hx > 0x3fd62e42) {     // |x| > ln2/2: reduce
    if (hx < 0x3FF0A2B2) {   // |x| < 1.5 ln2: k = +-1
      hi = negative ? x + detail::kLn2Hi : x - detail::kLn2Hi;
      lo = negative ? -detail::kLn2Lo : detail::kLn2Lo;
      k = negative ? -1 : 1;
    } else {
      k = static_cast<int>(inv_ln2 * x + (negative ? -0.5 : 0.5));
      const double t = k;
      hi = x - t * detail::kLn2Hi;  // exact: t * detail::kLn2Hi has few enough bits
      lo = t * detail::kLn2Lo;
    }
    x = hi - lo;
  } else if (hx < 0x3e300000) {  // |x| < 2^-28: e^x rounds to 1 + x
    return 1.0 + x;
  }

  const double t = x * x;
  const double c = x - t * (P1 + t * (P2 + t * (P3 + t * (P4 + t * P5))));
  if (k == 0) return 1.0 - ((x * c) / (c - 2.0) - x);
  const double y = 1.0 - ((lo - (x * c) / (2.0 - c)) - hi);
  // Scale by 2^k in steps that stay exact until the one final rounding.
  if (k >= -1021) {
    if (k == 1024) return y * 2.0 * 0x1p1023;
    return y * detail::pow2(k);
  }
  return y * detail::pow2(k + 1000) * 0x1p-1000;  // subnormal result: rounded once, here
}

AXG_HDI double sin(double x) {
  const std::uint32_t ix = detail::high_word(x) & 0x7fffffff;
  if (ix <= 0x3fe921fb) {                  // |x| <~ pi/4
    if (ix < 0x3e500000) return x;         // |x| < 2^-26: sin x rounds to x (keeps -0)
    return detail::kernel_sin(x, 0.0, false);
  }
  if (ix >= 0x7ff00000) return detail::trig_of_non_finite(x);
  double y0 = 0.0;
  double y1 = 0.0;
  switch (detail::rem_pio2(x, y0, y1) & 3) {
    case 0: return detail::kernel_sin(y0, y1, true);
    case 1: return detail::kernel_cos(y0, y1);
    case 2: return -detail::kernel_sin(y0, y1, true);
    default: return -detail::kernel_cos(y0, y1);
  }
}

AXG_HDI double cos(double x) {
  const std::uint32_t ix = detail::high_word(x) & 0x7fffffff;
  if (ix <= 0x3fe921fb) {                  // |x| <~ pi/4
    if (ix < 0x3e46a09e) return 1.0;       // |x| < 2^-27 sqrt(2): cos x rounds to 1
    return detail::kernel_cos(x, 0.0);
  }
  if (ix >= 0x7ff00000) return detail::trig_of_non_finite(x);
  double y0 = 0.0;
  double y1 = 0.0;
  switch (detail::rem_pio2(x, y0, y1) & 3) {
    case 0: return detail::kernel_cos(y0, y1);
    case 1: return -detail::kernel_sin(y0, y1, true);
    case 2: return -detail::kernel_cos(y0, y1);
    default: return detail::kernel_sin(y0, y1, true);
  }
}

// sin(x) and cos(x), bit-identical to the two calls, with one range reduction.
AXG_HDI void sincos(double x, double* s, double* c) {
  const std::uint32_t ix = detail::high_word(x) & 0x7fffffff;
  if (ix <= 0x3fe921fb) {
    *s = ix < 0x3e500000 ? x : detail::kernel_sin(x, 0.0, false);
    *c = ix < 0x3e46a09e ? 1.0 : detail::kernel_cos(x, 0.0);
    return;
  }
  if (ix >= 0x7ff00000) {
    *s = *c = detail::trig_of_non_finite(x);
    return;
  }
  double y0 = 0.0;
  double y1 = 0.0;
  const int n = detail::rem_pio2(x, y0, y1);
  const double sn = detail::kernel_sin(y0, y1, true);
  const double cs = detail::kernel_cos(y0, y1);
  switch (n & 3) {
    case 0: *s = sn; *c = cs; break;
    case 1: *s = cs; *c = -sn; break;
    case 2: *s = -sn; *c = -cs; break;
    default: *s = -cs; *c = sn; break;
  }
}

// sin(2 pi u) and cos(2 pi u) for u in [0, 1), reduced exactly: 8u = octant + fraction is exact,
// so 2 pi u = q pi/2 + r pi/4 with q the nearest quarter turn and r = 8u - 2q in [-1, 1) exact.
// Only r pi/4 is rounded, kept as a double-double, so the result is within 1 ulp of the true
// sin/cos of the exact angle 2 pi u (unlike sin(2 * pi * u), whose argument is rounded).
// Quarter turns are exact: u = 0, 1/4, 1/2, 3/4 give (0, 1), (1, 0), (0, -1), (-1, 0), every
// zero +0.
AXG_HDI void sincos_turns(double u, double* s, double* c) {
  constexpr double pio4_hi = 0x1.921fb54442d18p-1;
  constexpr double pio4_lo = 0x1.1a62633145c07p-55;  // pi/4 - pio4_hi
  constexpr double splitter = 0x1p27 + 1.0;           // Veltkamp split into 26 + 27 bits

  const double eighths = 8.0 * u;                             // exact
  const int octant = static_cast<int>(eighths);               // floor, u >= 0
  const int quadrant = (octant + 1) >> 1;                     // nearest quarter turn, 0..4
  const double r = eighths - 2.0 * static_cast<double>(quadrant);  // exact, in [-1, 1)

  // r * pio4_hi exactly as product + error (Dekker, no FMA), then the pio4_lo term.
  const double product = r * pio4_hi;
  const double r_big = splitter * r;
  const double r_hi = r_big - (r_big - r);
  const double r_lo = r - r_hi;
  const double p_big = splitter * pio4_hi;
  const double p_hi = p_big - (p_big - pio4_hi);
  const double p_lo = pio4_hi - p_hi;
  const double error = ((r_hi * p_hi - product) + r_hi * p_lo + r_lo * p_hi) + r_lo * p_lo;
  const double lo = error + r * pio4_lo;
  const double x = product + lo;
  const double tail = lo - (x - product);

  const double sn = detail::kernel_sin(x, tail, true);
  const double cs = detail::kernel_cos(x, tail);
  // Quadrant fix-up without branches (the quadrant of a random angle is unpredictable):
  // odd quadrants swap sin and cos; signs follow the quadrant. 0.0 - v rather than -v,
  // so that the exact zeros at quarter turns come out as +0.
  const std::uint64_t swap = 0 - static_cast<std::uint64_t>(quadrant & 1);
  const std::uint64_t neg_s = 0 - static_cast<std::uint64_t>((quadrant >> 1) & 1);
  const std::uint64_t neg_c = 0 - static_cast<std::uint64_t>(((quadrant + 1) >> 1) & 1);
  const std::uint64_t a = (bits_of(cs) & swap) | (bits_of(sn) & ~swap);
  const std::uint64_t b = (bits_of(sn) & swap) | (bits_of(cs) & ~swap);
  const std::uint64_t na = bits_of(0.0 - double_of(a)), nb = bits_of(0.0 - double_of(b));
  *s = double_of((na & neg_s) | (a & ~neg_s));
  *c = double_of((nb & neg_c) | (b & ~neg_c));
}

}  // namespace axg::core::pm
