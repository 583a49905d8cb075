#include "axonguide/support/error.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>

namespace axg {

std::uint64_t physical_memory_bytes() {
  long pages = sysconf(_SC_PHYS_PAGES);
  long page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
}

std::uint64_t peak_rss_bytes() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  std::uint64_t kb = 0;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "VmHWM: %lu kB", &kb) == 1) break;
  std::fclose(f);
  return kb * 1024;
}

std::string human_bytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 6) {
    bytes /= 1024.0;
    ++u;
  }
  return fmt::format("{:.3g} {}", bytes, units[u]);
}

namespace {
// Bytes of address space the process maps now (VmSize).
std::uint64_t mapped_bytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long pages = 0;
  const int got = std::fscanf(f, "%lu", &pages);
  std::fclose(f);
  return got == 1 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(sysconf(_SC_PAGE_SIZE)) : 0;
}
}  // namespace

std::uint64_t usable_memory_bytes(std::string* why) {
  std::uint64_t have = physical_memory_bytes();
  if (why) *why = fmt::format("this machine has {}", human_bytes(static_cast<double>(have)));
  rlimit lim{};
  if (::getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY) {
    // Thread stacks and the allocator's arenas come out of the same limit: keep 64 MiB.
    const std::uint64_t limit = lim.rlim_cur, used = mapped_bytes() + (std::uint64_t{64} << 20);
    const std::uint64_t left = limit > used ? limit - used : 0;
    if (have == 0 || left < have) {
      have = left;
      if (why)
        *why = fmt::format("the address-space limit (ulimit -v {} KiB) leaves this process {}", limit / 1024,
                           human_bytes(static_cast<double>(left)));
    }
  }
  return have;
}

void check_memory_estimate(std::uint64_t bytes, const std::string& what) {
  std::string why;
  const std::uint64_t have = usable_memory_bytes(&why);
  if (have != 0 && bytes > have) {
    throw RunError(fmt::format("{} needs an estimated {} but {}", what, human_bytes(static_cast<double>(bytes)), why));
  }
}

}  // namespace axg
