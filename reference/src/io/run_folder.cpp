// The run folder's protocol: ownership, the lock, the manifest's status and verification.
#include "axonguide/io/run_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "axonguide/engine/checkpoint.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/fault.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/io/sonata.hpp"
#include "axonguide/version.hpp"

namespace axg {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::set<std::string>& fixed_outputs() {
  static const std::set<std::string> names = [] {
    std::set<std::string> n{"neurons.csv",   "connections.csv", "stats.csv",     "bfs.csv",
                            "paths.csv",     "sources.csv",     "particles.csv", "graph.graphml", "synapses.csv",
                            "timings.csv",   "growth.pvd",      kManifestName,   kCheckpointName};
    n.insert(std::begin(kSonataFiles), std::end(kSonataFiles));
    return n;
  }();
  return names;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The subfolders a run writes, and the files in them that are a run's: one per VTK frame
// ("vtk/*.vtp" in a manifest's plan) and one per neuron's morphology ("morphologies/*.swc");
// network/ holds the fixed SONATA files.
struct Subfolder {
  const char* name;
  const char* extension;  // every file with it is a run's; nullptr: only the fixed names
  const char* pattern;    // how a plan lists them all
};
constexpr Subfolder kSubfolders[] = {
    {"vtk", ".vtp", "vtk/*.vtp"}, {"morphologies", ".swc", "morphologies/*.swc"}, {"network", nullptr, nullptr}};

std::vector<fs::path> run_dirs(const fs::path& dir) {
  std::vector<fs::path> dirs{dir};
  for (const Subfolder& s : kSubfolders) dirs.push_back(dir / s.name);
  return dirs;
}

void remove_empty_subfolders(const fs::path& dir) {
  std::error_code ec;
  for (const Subfolder& s : kSubfolders)
    if (fs::is_directory(dir / s.name, ec) && fs::is_empty(dir / s.name, ec)) fs::remove(dir / s.name, ec);
}

bool is_subfolder(const std::string& name) {
  for (const Subfolder& s : kSubfolders)
    if (name == s.name) return true;
  return false;
}

// AtomicFile's temporary name for an output NAME.
bool is_temporary(const std::string& file) {
  const std::optional<TemporaryName> t = parse_temporary_name(file);
  if (!t) return false;
  for (const std::string& output : fixed_outputs())
    if (fs::path(output).filename() == t->name) return true;
  return ends_with(t->name, ".vtp") || ends_with(t->name, ".swc");
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// A listed name must stay inside the folder.
bool safe_relative(const std::string& name) {
  if (name.empty() || name[0] == '/') return false;
  for (const auto& part : fs::path(name))
    if (part == ".." || part == ".") return false;
  return true;
}

void remove_file(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
  if (ec) throw RunError(fmt::format("cannot remove {}: {}", p.string(), ec.message()));
}

// A manifest's bytes: a regular file of at most 64 MiB (a run's is a few KiB, a line a file).
std::string read_manifest_bytes(const fs::path& dir) {
  return read_input_file((dir / kManifestName).string(), "manifest", std::size_t{64} << 20);
}

}  // namespace

bool is_run_output(const std::string& name) {
  if (fixed_outputs().count(name) != 0) return true;
  for (const Subfolder& s : kSubfolders)
    if (s.extension && name.rfind(std::string(s.name) + "/", 0) == 0 && ends_with(name, s.extension) &&
        name.find('/', std::strlen(s.name) + 1) == std::string::npos)
      return true;
  return false;
}

json read_manifest(const fs::path& dir) {
  const fs::path p = dir / kManifestName;
  std::error_code ec;
  if (!fs::exists(p, ec)) throw InputError(fmt::format("{}: no {} (not a run's folder)", dir.string(), kManifestName));
  const std::string text = read_manifest_bytes(dir);
  try {
    json j = parse_json_strict(text, p.string());
    if (!j.is_object()) throw InputError("not a JSON object");
    // The keys the command reads with a default, of the type it reads them as: another type
    // is a damaged manifest (exit 2), not a JSON library's type error.
    for (const char* key : {"status", "created"})
      if (j.contains(key) && !j[key].is_string()) throw InputError(fmt::format("\"{}\" is not a string", key));
    if (j.contains("axonguide")) {
      const json& by = j["axonguide"];
      if (!by.is_object()) throw InputError("\"axonguide\" is not an object");
      for (const char* key : {"version", "commit"})
        if (by.contains(key) && !by[key].is_string())
          throw InputError(fmt::format("\"axonguide\".\"{}\" is not a string", key));
    }
    return j;
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {} is not a manifest: {}", dir.string(), kManifestName, e.what()));
  }
}

FolderCheck verify_run_folder(const fs::path& dir) {
  FolderCheck c;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    c.problems.push_back(fmt::format("{} is not a directory", dir.string()));
    return c;
  }
  try {
    c.manifest = read_manifest(dir);
  } catch (const InputError& e) {
    c.problems.push_back(e.what());
    return c;
  }
  const json& m = c.manifest;
  if (m.contains("status") && m["status"].is_string()) c.status = m["status"].get<std::string>();
  else if (!m.contains("status")) c.status = "complete";  // manifests from before the status field
  if (c.status == "running")
    c.problems.push_back("status \"running\": a run is writing this folder, or was killed while it did "
                         "(continue it with `axonguide run --resume DIR`)");
  else if (c.status == "interrupted")
    c.problems.push_back("status \"interrupted\": the run stopped before its outputs were written "
                         "(continue it with `axonguide run --resume DIR`)");
  else if (c.status != "complete")
    c.problems.push_back(fmt::format("status {}: not one of running, interrupted, complete", m.value("status", json()).dump()));
  if (!m.contains("files") || !m["files"].is_object()) {
    c.problems.push_back("the manifest lists no files");
  } else if (c.status == "complete") {
    if (m["files"].empty()) c.problems.push_back("the manifest lists no files");
    for (auto it = m["files"].begin(); it != m["files"].end(); ++it) {
      const std::string name = it.key();
      if (!safe_relative(name)) {
        c.problems.push_back(fmt::format("{}: a name outside the folder", printable(name)));
        continue;
      }
      const fs::path p = dir / name;
      if (!fs::is_regular_file(p, ec)) {
        c.problems.push_back(fmt::format("{}: missing", printable(name)));
        continue;
      }
      const json& want = it.value();
      if (!want.is_object() || !want.contains("sha256") || !want["sha256"].is_string()) {
        c.problems.push_back(fmt::format("{}: no sha256 in the manifest", printable(name)));
        continue;
      }
      std::string got;
      try {
        got = sha256_file(p);
      } catch (const RunError& e) {
        c.problems.push_back(fmt::format("{}: {}", printable(name), e.what()));
        continue;
      }
      if (got != want["sha256"].get<std::string>())
        c.problems.push_back(fmt::format("{}: SHA-256 {} but the manifest lists {}", printable(name),
                                         got.substr(0, 16) + "…",
                                         printable(want["sha256"].get<std::string>().substr(0, 16)) + "…"));
    }
  }
  if (fs::exists(dir / kCheckpointName, ec) && c.status == "complete")
    c.notes.push_back(fmt::format("{} is left from before the outputs were complete (not needed)", kCheckpointName));
  if (fs::exists(dir / kReplacedName, ec)) {
    if (c.status != "complete" && keeps_replaced_run(m))
      c.notes.push_back(fmt::format("{}/ keeps the complete run that this one replaces: it is put back if this run "
                                    "fails before its first checkpoint, and removed when this run completes",
                                    kReplacedName));
    else
      c.notes.push_back(fmt::format("{}/ is left from a run that --force replaced (not needed; `axonguide run "
                                    "--resume` or a --force run into this folder removes it)",
                                    kReplacedName));
  }
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (is_temporary(e.path().filename().string()))
      c.notes.push_back(fmt::format("{}: a temporary file of a killed run", printable(e.path().filename().string())));
  c.whole = c.problems.empty();
  return c;
}

json require_whole_run(const fs::path& dir, const std::string& command) {
  const FolderCheck c = verify_run_folder(dir);
  if (c.whole) return c.manifest;
  std::string why;
  for (const auto& p : c.problems) why += (why.empty() ? "" : "; ") + p;
  throw InputError(fmt::format("{}: {} is not a whole run: {} (see `axonguide verify {}`)", command, dir.string(), why,
                               dir.string()));
}

FolderLock::FolderLock(const fs::path& dir) : path_(dir / kLockName) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw RunError(fmt::format("cannot create the lock {}: {}", path_.string(), std::strerror(errno)));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      char pid[32] = {0};
      const ssize_t got = ::pread(fd_, pid, sizeof pid - 1, 0);
      ::close(fd_);
      fd_ = -1;
      if (err == EWOULDBLOCK)
        throw RunError(fmt::format("{}: another axonguide run (pid {}) is writing this folder; wait for it, or choose "
                                   "another --out",
                                   dir.string(), got > 0 ? std::string(pid, static_cast<std::size_t>(got)) : "?"));
      throw RunError(fmt::format("cannot lock {}: {}", path_.string(), std::strerror(err)));
    }
    // The holder before us may have removed the file after we opened it: then our lock is
    // on an unlinked inode, and we try again.
    struct stat held {}, named {};
    if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
        held.st_dev == named.st_dev) {
      const std::string pid = std::to_string(::getpid());
      if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) < 0) {
        // The pid is only for the message of a second run.
      }
      return;
    }
    ::close(fd_);
    fd_ = -1;
  }
  throw RunError(fmt::format("cannot lock {}: it keeps being replaced", path_.string()));
}

FolderLock::~FolderLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());
  ::close(fd_);
}

void remove_stale_temporaries(const fs::path& dir) {
  std::error_code ec;
  for (const fs::path& d : run_dirs(dir)) {
    if (!fs::is_directory(d, ec)) continue;
    std::vector<fs::path> stale;
    for (const auto& e : fs::directory_iterator(d, ec))
      if (is_temporary(e.path().filename().string())) stale.push_back(e.path());
    for (const auto& p : stale) fs::remove(p, ec);
  }
}

namespace {

// Whether `name` is a run output of the subfolder that `pattern` ("vtk/*.vtp") names.
bool in_pattern(const std::string& pattern, const std::string& name) {
  for (const Subfolder& s : kSubfolders)
    if (s.pattern && pattern == s.pattern) return name.rfind(std::string(s.name) + "/", 0) == 0 && is_run_output(name);
  return false;
}

}  // namespace

FolderClaim claim_run_folder(const fs::path& dir, bool force) {
  std::error_code ec;
  std::vector<std::string> outputs;
  FolderClaim claim;
  for (const fs::path& d : run_dirs(dir)) {
    if (!fs::is_directory(d, ec)) continue;
    for (const auto& e : fs::directory_iterator(d, ec)) {
      const std::string name = fs::relative(e.path(), dir, ec).generic_string();
      if (name == kLockName || name == kReplacedName || is_subfolder(name) || is_temporary(e.path().filename().string()))
        continue;
      (is_run_output(name) ? outputs : claim.foreign).push_back(name);
    }
  }
  std::sort(outputs.begin(), outputs.end());
  std::sort(claim.foreign.begin(), claim.foreign.end());
  if (outputs.empty()) return claim;
  if (!fs::exists(dir / kManifestName, ec)) {
    std::string list;
    for (std::size_t k = 0; k < outputs.size() && k < 5; ++k) list += (k ? ", " : "") + outputs[k];
    throw InputError(fmt::format("--out {}: holds run outputs ({}{}) but no manifest.json, so nothing says which run "
                                 "they belong to; remove them or choose another folder",
                                 dir.string(), list, outputs.size() > 5 ? ", ..." : ""));
  }
  const json m = read_manifest(dir);
  const std::string status = m.value("status", std::string("complete"));
  if (!force) {
    if (status == "complete")
      throw InputError(fmt::format("--out {}: holds another run (created {}); give --force to replace it (it replaces "
                                   "exactly the files its manifest lists, and puts them back if the new run fails "
                                   "before its first checkpoint), or choose another folder",
                                   dir.string(), m.value("created", std::string("?"))));
    throw InputError(fmt::format("--out {}: holds an unfinished run (status \"{}\"); continue it with `axonguide run "
                                 "--resume {}`, or give --force to replace it",
                                 dir.string(), printable(status), dir.string()));
  }
  // The files the manifest lists; an unfinished run lists what it plans and what it
  // was replacing.
  std::set<std::string> listed{kManifestName, kCheckpointName};
  if (m.contains("files") && m["files"].is_object())
    for (auto it = m["files"].begin(); it != m["files"].end(); ++it) listed.insert(it.key());
  for (const char* key : {"planned", "replacing"})
    if (m.contains(key) && m[key].is_array())
      for (const auto& name : m[key])
        if (name.is_string()) listed.insert(name.get<std::string>());
  auto listed_by_pattern = [&](const std::string& name) {
    for (const std::string& pattern : listed)
      if (in_pattern(pattern, name)) return true;
    return false;
  };
  // A complete run is kept until the new one is whole; an unfinished one that was itself
  // replacing a complete run keeps that one (and moves there what it had not yet moved).
  std::set<std::string> keeping;
  if (status == "complete") {
    claim.replaced = FolderClaim::Replaced::kMake;
  } else if (keeps_replaced_run(m) && fs::exists(dir / kReplacedName / kManifestName, ec)) {
    claim.replaced = FolderClaim::Replaced::kKeep;
    if (m.contains("replacing") && m["replacing"].is_array())
      for (const auto& name : m["replacing"])
        if (name.is_string()) keeping.insert(name.get<std::string>());
  }
  for (const std::string& name : outputs) {
    if ((listed.count(name) != 0 || listed_by_pattern(name)) && safe_relative(name))
      (keeping.count(name) != 0 ? claim.keeping : claim.replacing).push_back(name);
    else
      claim.foreign.push_back(name);
  }
  std::sort(claim.foreign.begin(), claim.foreign.end());
  return claim;
}

void refuse_foreign_in_the_way(const fs::path& dir, const FolderClaim& claim, const Scene& scene) {
  const std::vector<std::string> planned = planned_outputs(scene);
  auto in_the_way = [&](const std::string& name) {
    for (const std::string& p : planned)
      if (p == name || in_pattern(p, name)) return true;
    return false;
  };
  std::vector<std::string> hit;
  for (const std::string& name : claim.foreign)
    if (in_the_way(name)) hit.push_back(name);
  if (hit.empty()) return;
  std::string names;
  for (const std::string& name : hit) names += (names.empty() ? "" : ", ") + name;
  const char* them = hit.size() == 1 ? "it" : "them";
  throw InputError(fmt::format("{}: {}: not listed by the old run's manifest, and this run would write over {}; move "
                               "{} out of the folder first",
                               dir.string(), names, them, them));
}

namespace {

// The files of DIR that `names` stand for (a subfolder's pattern for all its run files),
// each relative to DIR; the manifest is never one of them.
std::vector<std::string> named_files(const fs::path& dir, const std::vector<std::string>& names) {
  std::error_code ec;
  std::vector<std::string> files;
  for (const std::string& name : names) {
    const Subfolder* all = nullptr;
    for (const Subfolder& s : kSubfolders)
      if (s.pattern && name == s.pattern) all = &s;
    if (all) {
      for (const auto& e : fs::directory_iterator(dir / all->name, ec)) {
        const std::string file = std::string(all->name) + "/" + e.path().filename().string();
        if (is_run_output(file)) files.push_back(file);
      }
    } else if (safe_relative(name) && is_run_output(name) && name != kManifestName && fs::exists(dir / name, ec)) {
      files.push_back(name);
    }
  }
  return files;
}

void move_file(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_directories(to.parent_path(), ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", to.parent_path().string(), ec.message()));
  fs::rename(from, to, ec);
  if (ec) throw RunError(fmt::format("cannot move {} to {}: {}", from.string(), to.string(), ec.message()));
}

}  // namespace

void remove_run_files(const fs::path& dir, const std::vector<std::string>& names) {
  for (const std::string& name : named_files(dir, names)) remove_file(dir / name);
  remove_stale_temporaries(dir);
  remove_empty_subfolders(dir);
}

bool keeps_replaced_run(const json& manifest) {
  return manifest.contains("replaced_run") && manifest["replaced_run"] == kReplacedName;
}

void make_replaced_run(const fs::path& dir) {
  const fs::path kept = dir / kReplacedName;
  std::error_code ec;
  fs::remove_all(kept, ec);  // one left by a run killed after it was whole
  if (!ec) fs::create_directory(kept, ec);
  if (ec) throw RunError(fmt::format("cannot make {} afresh: {}", kept.string(), ec.message()));
  AtomicFile copy(kept, kManifestName);  // its own bytes, synced before the running manifest replaces it
  copy.write(read_manifest_bytes(dir));
  copy.commit();
}

void keep_replaced_files(const fs::path& dir, const std::vector<std::string>& names) {
  const fs::path kept = dir / kReplacedName;
  std::error_code ec;
  for (const std::string& name : named_files(dir, names)) {
    if (fs::exists(kept / name, ec))
      remove_file(dir / name);
    else
      move_file(dir / name, kept / name);
    fault_point("keep " + name);
  }
  remove_stale_temporaries(dir);
  remove_empty_subfolders(dir);
}

bool restore_replaced_run(const fs::path& dir) {
  const fs::path kept = dir / kReplacedName;
  std::error_code ec;
  if (!fs::is_regular_file(kept / kManifestName, ec)) return false;
  const json old = read_manifest(kept);
  std::vector<std::string> files;
  if (old.contains("files") && old["files"].is_object())
    for (auto it = old["files"].begin(); it != old["files"].end(); ++it)
      if (safe_relative(it.key()) && is_run_output(it.key()) && it.key() != kManifestName) files.push_back(it.key());
  // The running manifest names them first, as files it replaces: a kill from here on
  // leaves a folder that the next run moves back into .replaced/ (FolderClaim::kKeep).
  json running = read_manifest(dir);
  running["replacing"] = files;
  write_manifest(dir, running);
  for (const std::string& name : files)
    if (fs::exists(kept / name, ec)) {
      move_file(kept / name, dir / name);
      fault_point("restore " + name);
    }
  move_file(kept / kManifestName, dir / kManifestName);
  sync_filesystem(dir);
  discard_replaced_run(dir);
  return true;
}

void discard_replaced_run(const fs::path& dir) {
  std::error_code ec;
  fs::remove_all(dir / kReplacedName, ec);
  if (ec)  // the new run is whole all the same; the next --force or run removes it
    std::fprintf(stderr, "axonguide: warning: cannot remove %s (the replaced run, no longer needed): %s\n",
                 (dir / kReplacedName).c_str(), ec.message().c_str());
}

json manifest_header(const Scene& scene, const std::string& backend, int threads,
                     const std::vector<std::string>& warnings) {
  json m;
  m["axonguide"] = {{"version", kVersion}, {"commit", kCommit}, {"build_type", kBuildType},
                    {"compiler", kCompiler}, {"cxx_flags", kCxxFlags}};
  m["scene"] = scene_to_json(scene);
  m["seed"] = scene.seed;
  m["units"] = scene.units.describe();
  m["backend"] = backend;
  m["threads"] = threads;
  m["created"] = utc_now();
  m["warnings"] = warnings;
  return m;
}

void write_manifest(const fs::path& dir, const json& manifest) {
  AtomicFile m(dir, kManifestName);
  m.write(manifest.dump(2));
  m.write("\n");
  m.commit();
}

}  // namespace axg
