#pragma once
// Physical units a scene may declare (SPEC §3.3). They name what the numbers mean; the
// model is the same in any consistent set. Without them: length units (LU), steps, and
// concentration units (CU: amount per LU^3).
#include <string>

namespace axg {

// The report's length unit read as micrometres: its soma radius 0.25 LU as 10 um.
inline constexpr double kMicrometresPerLu = 40.0;

struct Units {
  std::string length = "LU";         // "LU" or "um"
  std::string time = "step";         // "step", "s", "min" or "h"
  std::string concentration = "CU";  // "CU", "pM", "nM" or "uM"
  bool declared() const { return length != "LU" || time != "step" || concentration != "CU"; }
  // "length um, time min, concentration nM"
  std::string describe() const;
  // Micrometres per length unit, for the formats that fix micrometres (SWC, SONATA).
  double micrometres() const { return length == "um" ? 1.0 : kMicrometresPerLu; }
};

}  // namespace axg
