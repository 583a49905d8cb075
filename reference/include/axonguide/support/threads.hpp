#pragma once
// Runs work on exactly `threads` TBB threads (0: all hardware threads), more than the
// machine has if asked: results never depend on it, which is what the tests check.
#include <functional>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

namespace axg {

inline int resolve_threads(int threads) {
  return threads > 0 ? threads : static_cast<int>(tbb::info::default_concurrency());
}

template <class Fn>
decltype(auto) with_threads(int threads, Fn&& fn) {
  const int n = resolve_threads(threads);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(n));
  tbb::task_arena arena(n);
  return arena.execute(std::forward<Fn>(fn));
}

}  // namespace axg
