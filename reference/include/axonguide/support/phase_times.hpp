#pragma once
// Phase timers: wall-clock time per (step, phase), which timings.csv writes. Every engine
// and every field times its phases with them.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace axg {

// Wall-clock time per (step, phase): the only output allowed to vary between runs.
class PhaseTimes {
 public:
  struct Row {
    std::uint32_t step;  // 0 for work outside the step loop
    std::string phase;
    double seconds;
  };
  void add(std::uint32_t step, const char* phase, double seconds) {
    rows_.push_back({step, phase, seconds});
  }
  const std::vector<Row>& rows() const { return rows_; }
  std::vector<Row>& rows() { return rows_; }
  double total(const std::string& phase) const {
    double t = 0;
    for (const auto& r : rows_)
      if (r.phase == phase) t += r.seconds;
    return t;
  }

 private:
  std::vector<Row> rows_;
};

class ScopedPhase {
 public:
  ScopedPhase(PhaseTimes& times, std::uint32_t step, const char* phase)
      : times_(times), step_(step), phase_(phase), start_(std::chrono::steady_clock::now()) {}
  ~ScopedPhase() {
    times_.add(step_, phase_,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

 private:
  PhaseTimes& times_;
  std::uint32_t step_;
  const char* phase_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace axg
