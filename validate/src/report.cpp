#include "axonguide/validate/report.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/version.hpp"

namespace axg::validate {

namespace fs = std::filesystem;

std::string num(double v, int digits) {
  if (v != v) return "nan";
  return fmt::format("{:.{}g}", v, digits);
}

fs::path plots_dir() {
  const char* env = std::getenv("AXG_PLOTS_DIR");
  return env && *env ? fs::path(env) : data_dir() / "validate" / "plots";
}

Report::Report(fs::path dir, std::string title) : dir_(std::move(dir)), title_(std::move(title)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) throw InputError(fmt::format("--report {}: cannot create directory: {}", dir_.string(), ec.message()));
}

void Report::heading(const std::string& title) { body_ += fmt::format("\n## {}\n\n", title); }

void Report::text(const std::string& markdown) { body_ += markdown + "\n\n"; }

namespace {
// Written whole under a temporary name and renamed; a failed write is a RunError (exit 3).
void write_csv(const fs::path& path, const std::vector<std::string>& header,
               const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& cells) {
    for (std::size_t k = 0; k < cells.size(); ++k) {
      std::string c = cells[k];
      if (c.find(',') != std::string::npos || c.find('"') != std::string::npos) {
        std::string q = "\"";
        for (char ch : c) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        c = q + "\"";
      }
      out << (k ? "," : "") << c;
    }
    out << "\n";
  };
  line(header);
  for (const auto& r : rows) line(r);
  write_file_atomically(path.parent_path(), path.filename().string(), out.str());
}
}  // namespace

void Report::csv(const std::string& name, const std::vector<std::string>& header,
                 const std::vector<std::vector<std::string>>& rows) {
  write_csv(dir_ / name, header, rows);
  body_ += fmt::format("Data: [`{}`]({})\n\n", name, name);
}

void Report::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                   const std::string& csv_name) {
  std::string md = "|";
  for (const auto& h : header) md += " " + h + " |";
  md += "\n|";
  for (std::size_t k = 0; k < header.size(); ++k) md += "---|";
  md += "\n";
  for (const auto& r : rows) {
    md += "|";
    for (const auto& c : r) md += " " + c + " |";
    md += "\n";
  }
  body_ += md + "\n";
  if (!csv_name.empty()) {
    write_csv(dir_ / csv_name, header, rows);
    body_ += fmt::format("Data: [`{}`]({})\n\n", csv_name, csv_name);
  }
}

void Report::check(Check c) { checks_.push_back(std::move(c)); }

void Report::skip(const std::string& name, const std::string& reason) {
  checks_.push_back({name, true, "SKIPPED", reason, "", true});
}

extern "C" char** environ;

int run_program(const std::vector<std::string>& argv, const fs::path& log, const std::string* input) {
  if (argv.empty()) return -1;
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string out = log.string();
  // Its standard input: a socket, not a pipe, so that a child that exits before reading it
  // all makes send() fail (MSG_NOSIGNAL) instead of killing this process with SIGPIPE.
  int sv[2] = {-1, -1};
  if (input && ::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) return -1;
  posix_spawn_file_actions_t fa;
  int rc = posix_spawn_file_actions_init(&fa);
  if (rc != 0) {  // nothing to destroy
    if (input) ::close(sv[0]), ::close(sv[1]);
    return -1;
  }
  rc = input ? posix_spawn_file_actions_adddup2(&fa, sv[1], 0)
             : posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  if (rc == 0 && !out.empty()) {
    rc = posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (rc == 0) rc = posix_spawn_file_actions_adddup2(&fa, 1, 2);
  }
  pid_t pid = -1;
  const int spawned = rc != 0 ? rc : ::posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (input) ::close(sv[1]);
  if (spawned != 0) {
    if (input) ::close(sv[0]);
    return -1;
  }
  if (input) {
    for (std::size_t sent = 0; sent < input->size();) {
      const ssize_t n = ::send(sv[0], input->data() + sent, input->size() - sent, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;  // it stopped reading: its exit status says why
      sent += static_cast<std::size_t>(n);
    }
    ::close(sv[0]);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;  // ECHILD: someone else reaped it (SIGCHLD ignored); nothing is left
  return status;
}

// The first Python that can import matplotlib: $AXG_PYTHON, Debian's /usr/bin/python3
// (python3-matplotlib), then python3 on PATH. Empty when there is none.
const std::string& plotting_python() {
  static const std::string found = [] {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("AXG_PYTHON"); env && *env) candidates.push_back(env);
    candidates.push_back("/usr/bin/python3");
    candidates.push_back("python3");
    for (const auto& c : candidates)
      if (run_program({c, "-c", "import matplotlib"}, "/dev/null") == 0) return c;
    return std::string();
  }();
  return found;
}

void Report::plot(const std::string& script, const std::vector<std::string>& csv_names, const std::string& png_name,
                  const std::string& caption) {
  const fs::path py = plots_dir() / script;
  if (plotting_python().empty()) {
    body_ += fmt::format("*(plot {} not made: no python3 with matplotlib; install python3-matplotlib)*\n\n", png_name);
    return;
  }
  std::vector<std::string> argv{plotting_python(), py.string()};
  for (const auto& c : csv_names) argv.push_back((dir_ / c).string());
  argv.push_back((dir_ / png_name).string());
  const int rc = run_program(argv, dir_ / (png_name + ".log"));
  if (rc == -1) {
    body_ += fmt::format("*(plot {} not made: {} could not be started)*\n\n", png_name, plotting_python());
  } else if (rc == 0 && fs::exists(dir_ / png_name)) {
    std::error_code ec;
    fs::remove(dir_ / (png_name + ".log"), ec);
    body_ += fmt::format("![{}]({})\n\n*{}*\n\n", caption, png_name, caption);
  } else {
    body_ += fmt::format("*(plot {} not made: python3 with matplotlib is needed; see {}.log)*\n\n", png_name, png_name);
  }
}

bool Report::passed() const {
  for (const auto& c : checks_)
    if (!c.pass || c.skipped) return false;
  return true;
}

std::size_t Report::skipped() const {
  std::size_t n = 0;
  for (const auto& c : checks_) n += c.skipped;
  return n;
}

int Report::finish(bool allow_skip) {
  std::ostringstream md;
  std::size_t failed = 0;
  const std::size_t skipped = this->skipped();
  for (const auto& c : checks_) failed += !c.pass;
  // A skipped check proved nothing: the report is SKIPPED, not PASS, even when allowed.
  const char* result = failed ? "FAIL" : skipped ? "SKIPPED" : "PASS";
  const std::string allowed = !failed && skipped && allow_skip ? ", allowed by --allow-skip" : "";
  md << "# " << title_ << "\n\n";
  md << fmt::format("axonguide {} ({}). **{}**{}: {} checks, {} failed, {} skipped.\n\n", kVersion, kCommit, result,
                    allowed, checks_.size(), failed, skipped);
  if (!checks_.empty()) {
    md << "| check | result | measured | criterion | margin |\n|---|---|---|---|---|\n";
    for (const auto& c : checks_)
      md << fmt::format("| {} | {} | {} | {} | {} |\n", c.name, c.skipped ? "SKIPPED" : c.pass ? "pass" : "**FAIL**",
                        c.measured, c.criterion, c.margin);
    md << "\n";
  }
  md << body_;
  std::ostringstream csv;
  csv << "check,result,measured,criterion,margin\n";
  for (const auto& c : checks_)
    csv << fmt::format("\"{}\",{},\"{}\",\"{}\",\"{}\"\n", c.name, c.skipped ? "skipped" : c.pass ? "pass" : "fail",
                       c.measured, c.criterion, c.margin);
  // Whole under their names, or a RunError (exit 3): a report that was not written is not a
  // PASS.
  write_file_atomically(dir_, "checks.csv", csv.str());
  write_file_atomically(dir_, "report.md", md.str());
  for (const auto& c : checks_)
    if (!c.pass)
      std::fprintf(stderr, "FAILED %s: measured %s; required %s (%s)\n", c.name.c_str(), c.measured.c_str(),
                   c.criterion.c_str(), c.margin.c_str());
    else if (c.skipped)
      std::fprintf(stderr, "SKIPPED %s: %s\n", c.name.c_str(), c.criterion.c_str());
  std::printf("%s: %s%s (%zu checks, %zu failed, %zu skipped) -> %s\n", title_.c_str(), result, allowed.c_str(),
              checks_.size(), failed, skipped, (dir_ / "report.md").c_str());
  std::fflush(stdout);
  if (failed) return kExitCheckFailed;
  return skipped && !allow_skip ? kExitCannotRun : kExitOk;
}

bool draw_folder_plot(const fs::path& dir, const std::string& script, const std::string& png,
                      const std::string& command, bool quiet_without_python) {
  {
    std::error_code ec;
    fs::remove(dir / png, ec);
  }
  const std::string& python = plotting_python();
  if (python.empty()) {
    if (!quiet_without_python)
      std::fprintf(stderr, "axonguide: %s: no python3 with matplotlib; %s not drawn\n", command.c_str(), png.c_str());
    return false;
  }
  const fs::path path = plots_dir() / script;
  if (run_program({python, path.string(), dir.string()}, "/dev/null") != 0) {
    std::fprintf(stderr, "axonguide: %s: %s failed; %s not drawn\n", command.c_str(), path.string().c_str(),
                 png.c_str());
    return false;
  }
  return true;
}

}  // namespace axg::validate
