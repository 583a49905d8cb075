#pragma once
// A test hook for crash consistency: when the environment variable AXG_FAULT_KILL_AT
// names a point ("placement", "setup", "step N", "checkpoint N", "output FILE",
// "manifest", "keep FILE" and "restore FILE": a replaced run's file moved into
// .replaced/ and back), the process sends itself SIGKILL there, as `kill -9` would. The
// resume tests use it to kill a run at exact points of every stage; unset, it costs a null
// test. AXG_FAULT_SIGNAL=INT, TERM or STOP sends that signal instead (the interruption and
// lock tests). AXG_FAULT_RANK=R limits it to rank R of an MPI job (the decomposed run's
// tests).
#include <string_view>

namespace axg {

void fault_point(std::string_view name);

}  // namespace axg
