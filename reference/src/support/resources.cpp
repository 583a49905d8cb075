#include "axonguide/support/resources.hpp"

#include <dlfcn.h>

#include <cstdlib>

namespace axg {

namespace fs = std::filesystem;

fs::path loaded_from() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&loaded_from), &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code ec;
  const fs::path self = fs::canonical(fs::path(info.dli_fname), ec);
  if (ec) {
    const fs::path exe = fs::canonical("/proc/self/exe", ec);
    return ec ? fs::path() : exe.parent_path();
  }
  return self.parent_path();
}

fs::path data_dir() {
  if (const char* env = std::getenv("AXG_SOURCE_DIR"); env && *env) return fs::path(env);
  static const fs::path found = [] {
    // bin/axonguide -> ../share/axonguide; lib/python3/dist-packages/axonguide/_core*.so
    // -> ../../../../share/axonguide.
    fs::path d = loaded_from();
    std::error_code ec;
    for (int up = 0; up < 5 && !d.empty(); ++up, d = d.parent_path()) {
      const fs::path share = d / "share" / "axonguide";
      if (fs::is_regular_file(share / ".axonguide-data", ec)) return share;
      if (d == d.parent_path()) break;
    }
    return fs::path(AXG_SOURCE_DIR);
  }();
  return found;
}

}  // namespace axg
