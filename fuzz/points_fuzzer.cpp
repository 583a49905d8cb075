// libFuzzer harness over the points-CSV reader of `axonguide validate samplers --points FILE`.
// A refusal is an InputError; anything else that escapes is a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "axonguide/support/error.hpp"
#include "axonguide/validate/points_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const axg::validate::PointRows p = axg::validate::read_points_csv(in, "--points fuzz.csv");
    // What the reader returns is what the tests downstream rely on.
    if (p.x.size() != p.n * static_cast<std::size_t>(p.d < 0 ? 0 : p.d)) __builtin_trap();
    if ((p.n == 0) != (p.d < 0)) __builtin_trap();
    for (double v : p.x)
      if (!std::isfinite(v)) __builtin_trap();
  } catch (const axg::InputError&) {
  }
  return 0;
}
