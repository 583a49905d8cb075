// The command's large allocations on transparent huge pages (docs/scaling.md §5).
//
// At 10^7 neurons every array of the run is tens to hundreds of MB, above glibc's mmap
// threshold (at most 32 MB), so each is a fresh mapping whose every 4 KiB page faults on
// first touch: 680,000 faults in a 10^7 direct run, several seconds in a virtual machine,
// and a cost that grows faster than the network (at 10^6 the arrays are below the
// threshold and reuse freed heap memory without faulting). Advising the kernel to back them
// with 2 MiB pages (MADV_HUGEPAGE, which the kernel's default "madvise" mode honours)
// divides the faults by about 30. Where transparent huge pages are off the advice does
// nothing. Only where memory lives changes, never a value: the outputs are the same bytes.
//
// These replace the global operator new and delete of the command (the library and the
// tests keep the standard ones); the array, nothrow and sized forms forward to them.
#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kAdviseFrom = 4 * kHugePage;  // below this a block spans few huge pages

void advise_huge_pages(void* p, std::size_t size) {
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t begin = (at + kHugePage - 1) & ~(kHugePage - 1), end = (at + size) & ~(kHugePage - 1);
  // Advice: when the kernel refuses it the block keeps its small pages, nothing else changes.
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

}  // namespace

void* operator new(std::size_t size) {
  for (;;) {
    if (void* p = std::malloc(size ? size : 1)) {
      if (size >= kAdviseFrom) advise_huge_pages(p, size);
      return p;
    }
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
