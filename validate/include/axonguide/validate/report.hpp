#pragma once
// A validation report: Markdown (report.md) with tables, CSV files for every table of
// numbers, PNG plots made by matplotlib scripts (validate/plots), and a list of checks.
// A report passes when every check passes; a failed check says by how much.
#include <filesystem>
#include <string>
#include <vector>

namespace axg::validate {

struct Check {
  std::string name;
  bool pass;
  std::string measured;   // the value found
  std::string criterion;  // what was required, fixed before the run
  std::string margin;     // by how much it passed or failed
  bool skipped = false;
};

class Report {
 public:
  Report(std::filesystem::path dir, std::string title);

  void heading(const std::string& title);
  void text(const std::string& markdown);
  // A Markdown table; with a non-empty csv_name also DIR/csv_name (same columns).
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
             const std::string& csv_name = "");
  // Only the CSV file (for long series that feed a plot), linked from the report.
  void csv(const std::string& name, const std::vector<std::string>& header,
           const std::vector<std::vector<std::string>>& rows);
  void check(Check c);
  // A check that could not run here (no GPU, too few data): recorded as SKIPPED, never a pass.
  void skip(const std::string& name, const std::string& reason);
  // Runs `python3 PLOTS/script.py CSV... PNG`; embeds the PNG, or notes why there is none.
  void plot(const std::string& script, const std::vector<std::string>& csv_names, const std::string& png_name,
            const std::string& caption);

  const std::vector<Check>& checks() const { return checks_; }
  // Every check ran and passed (a skipped check is not a pass).
  bool passed() const;
  std::size_t skipped() const;
  // Writes report.md and checks.csv; returns the process exit code: 1 when a check failed,
  // else 3 when one was skipped (it could not run here) unless allow_skip, else 0. The
  // report says SKIPPED, not PASS, when a check was skipped, allowed or not.
  int finish(bool allow_skip = false);
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::string title_;
  std::string body_;
  std::vector<Check> checks_;
};

// Number formatting for reports.
std::string num(double v, int digits = 4);

// The first Python that can import matplotlib ($AXG_PYTHON, /usr/bin/python3, python3);
// empty when there is none.
const std::string& plotting_python();

// Runs argv[0] (looked up on PATH) with these arguments and no shell, so that no byte of a
// folder's name is ever taken for shell syntax. Standard output and error go to `log`
// (created or truncated; "/dev/null" discards them), or are this process's when it is
// empty; `input`, when given, is written
// to its standard input (else it reads /dev/null). Returns the wait status (0: exited 0),
// or -1 when it could not start.
int run_program(const std::vector<std::string>& argv, const std::filesystem::path& log = {},
                const std::string* input = nullptr);

// Where the plotting scripts live: AXG_PLOTS_DIR, or validate/plots under data_dir()
// (axonguide/support/resources.hpp: the installed share/axonguide, or the source tree).
std::filesystem::path plots_dir();

// A command's picture of its own output folder: removes DIR/png (so that a plot not drawn
// leaves no older picture beside new numbers), then runs plots_dir()/script DIR. Says on
// standard error, as `command`, when it failed, and when there is no Python with matplotlib
// unless quiet_without_python. Returns whether the picture was drawn.
bool draw_folder_plot(const std::filesystem::path& dir, const std::string& script, const std::string& png,
                      const std::string& command, bool quiet_without_python = false);

}  // namespace axg::validate
