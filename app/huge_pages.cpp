// The command's large allocations on transparent huge pages, touched in parallel
// (docs/scaling.md §5).
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
// The first touch of a fresh block zeroes its pages in the kernel, on the thread that
// touches them. A std::vector's construction value-initialises its elements on one
// thread, so at 10^7 neurons every large array was zeroed serially (about 2.5 GB in a
// direct run). Blocks of 32 MB and more are therefore touched once, a page in every 4 KiB,
// by the run's threads in parallel as they are allocated; the serial initialisation that
// follows then writes to pages already present. Only a block's pages are touched, and
// only writes of zero to memory that operator new hands out uninitialised: no value a
// caller reads changes. The peak rises only by blocks allocated and never used whole
// (the 10^7 direct run's peak stays 992 MB).
//
// These replace the global operator new and delete of the command (the library and the
// tests keep the standard ones); the array, nothrow and sized forms forward to them.
#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kAdviseFrom = 4 * kHugePage;  // below this a block spans few huge pages

void advise_huge_pages(void* p, std::size_t size) {
  const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t begin = (at + kHugePage - 1) & ~(kHugePage - 1), end = (at + size) & ~(kHugePage - 1);
  // Advice: when the kernel refuses it the block keeps its small pages, nothing else changes.
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

constexpr std::size_t kTouchFrom = 16 * kHugePage;
constexpr std::size_t kSmallPage = 4096;

// Isolated: while it waits, a thread runs only this loop's chunks, never a task of the
// parallel loop that allocated (which could reach the same thread-local buffer the
// allocation is growing).
void touch_in_parallel(void* p, std::size_t size) {
  char* const c = static_cast<char*>(p);
  const std::size_t chunks = (size + kHugePage - 1) / kHugePage;
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t k = r.begin(); k != r.end(); ++k) {
        const std::size_t end = std::min(size, (k + 1) * kHugePage);
        for (std::size_t q = k * kHugePage; q < end; q += kSmallPage) *reinterpret_cast<volatile char*>(c + q) = 0;
      }
    });
  });
}

}  // namespace

void* operator new(std::size_t size) {
  for (;;) {
    if (void* p = std::malloc(size ? size : 1)) {
      if (size >= kAdviseFrom) advise_huge_pages(p, size);
      if (size >= kTouchFrom) touch_in_parallel(p, size);
      return p;
    }
    const std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
