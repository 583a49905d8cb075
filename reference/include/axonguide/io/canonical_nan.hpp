#pragma once
// Numbers as the output files write them: every NaN becomes the one quiet NaN
// 0x7ff8000000000000, whatever its sign and payload (x86 and NVIDIA make different NaNs,
// and fmt prints a NaN with the sign bit as "-nan"). So a text file spells it "nan" and a
// binary VTK array holds that one bit pattern (docs/methods.md §4.2). Other values pass
// through unchanged, -0 and infinities included.
#include "axonguide/core/hd.hpp"
#include "axonguide/core/vec3.hpp"

namespace axg {

inline constexpr std::uint64_t kCanonicalNanBits = 0x7ff8000000000000ull;

inline double canonical(double x) {
  return (core::bits_of(x) & 0x7fffffffffffffffull) > 0x7ff0000000000000ull ? core::double_of(kCanonicalNanBits) : x;
}

inline core::Vec3 canonical(core::Vec3 v) { return {canonical(v.x), canonical(v.y), canonical(v.z)}; }

}  // namespace axg
