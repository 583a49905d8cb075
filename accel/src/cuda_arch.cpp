// Which GPUs a list of CUDA architectures runs on: compiled into the host dispatcher
// (accel.cpp) and into the CUDA plugin (engine_cuda.cu), which both judge it.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string>
#include <vector>

#include "axonguide/accel/engines.hpp"

namespace axg::accel {

std::string cuda_arch_refusal(int major, int minor, const std::string& archs) {
  const int device = major * 10 + minor;
  bool runs = false;
  std::vector<std::string> have;
  std::size_t begin = 0;
  while (begin <= archs.size()) {
    const std::size_t end = std::min(archs.find(',', begin), archs.size());
    std::string a = archs.substr(begin, end - begin);
    begin = end + 1;
    if (a.empty()) continue;
    bool sass = true, ptx = true;
    if (a.size() > 5 && a.compare(a.size() - 5, 5, "-real") == 0) ptx = false, a.resize(a.size() - 5);
    else if (a.size() > 8 && a.compare(a.size() - 8, 8, "-virtual") == 0) sass = false, a.resize(a.size() - 8);
    std::size_t digits = 0;
    while (digits < a.size() && a[digits] >= '0' && a[digits] <= '9') ++digits;
    const std::string suffix = a.substr(digits);
    if (digits < 2 || (suffix != "" && suffix != "a" && suffix != "f")) return {};  // native, all, all-major
    const int cc = std::stoi(a.substr(0, digits));
    const int cmaj = cc / 10, cmin = cc % 10;
    // sm_XYa and compute_XYa: X.Y only; sm_XYf and compute_XYf: the family X.Y to X.9.
    const bool exact = suffix == "a", family = suffix == "f";
    if (sass) {
      runs = runs || (exact ? device == cc : major == cmaj && minor >= cmin);
      have.push_back(fmt::format("sm_{} ({}.{}{})", a, cmaj, cmin, exact ? " only" : fmt::format(" to {}.9", cmaj)));
    }
    if (ptx) {
      runs = runs || (exact ? device == cc : family ? major == cmaj && minor >= cmin : device >= cc);
      have.push_back(fmt::format("PTX compute_{} ({}.{}{}, through the driver's JIT)", a, cmaj, cmin,
                                 exact ? " only" : family ? fmt::format(" to {}.9", cmaj) : " and newer"));
    }
  }
  if (runs || have.empty()) return {};
  std::string cmake_list = archs;
  std::replace(cmake_list.begin(), cmake_list.end(), ',', ';');
  return fmt::format(
      "compute capability {}.{}, which this build cannot run: it has code for {}; rebuild with "
      "-DCMAKE_CUDA_ARCHITECTURES=\"{}-real;{}\" or use --backend reference",
      major, minor, fmt::join(have, ", "), device, cmake_list);
}

}  // namespace axg::accel
