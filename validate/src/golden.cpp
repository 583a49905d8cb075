#include "axonguide/validate/golden.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "axonguide/support/error.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/support/resources.hpp"
#include "axonguide/support/threads.hpp"
#include "axonguide/validate/report.hpp"
#include "axonguide/version.hpp"

namespace axg::validate {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every network folder under dir: each subdirectory is one, whether or not its files are
// all there (a network with a file missing is a failure, never a network skipped).
std::vector<fs::path> golden_networks(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw InputError(fmt::format("golden: {} is not a directory", dir.string()));
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  if (out.empty()) throw InputError(fmt::format("golden: no NAME/scene.json under {}", dir.string()));
  return out;
}

// A golden network verifies when scene.json is there and reads as the scene its
// provenance.json records, and expected/ holds exactly the files provenance lists, with
// their SHA-256. Returns why not (empty: it verifies).
std::vector<std::string> verify_network(const fs::path& g) {
  std::vector<std::string> why;
  if (!fs::exists(g / "provenance.json")) return {"provenance.json missing (not a blessed network)"};
  json prov;
  try {
    prov = json::parse(read_all(g / "provenance.json"));
  } catch (const json::exception& e) {
    return {fmt::format("provenance.json is not JSON ({})", e.what())};
  }
  if (!fs::exists(g / "scene.json")) {
    why.push_back("scene.json missing");
  } else {
    try {
      const Scene scene = load_scene_file((g / "scene.json").string()).scene;
      if (!prov.contains("scene") || scene_to_json(scene) != prov["scene"])
        why.push_back("scene.json is not the scene provenance.json was blessed with");
    } catch (const InputError& e) {
      why.push_back(fmt::format("scene.json: {}", e.what()));
    }
  }
  if (!prov.contains("files") || !prov["files"].is_object() || prov["files"].empty()) {
    why.push_back("provenance.json lists no expected files");
    return why;
  }
  for (auto it = prov["files"].begin(); it != prov["files"].end(); ++it) {
    const fs::path f = g / "expected" / it.key();
    if (!fs::exists(f)) why.push_back(fmt::format("expected/{}: missing", it.key()));
    else if (!it.value().is_string() || sha256_file(f) != it.value().get<std::string>())
      why.push_back(fmt::format("expected/{}: SHA-256 differs from provenance.json", it.key()));
  }
  if (fs::is_directory(g / "expected"))
    for (const auto& e : fs::directory_iterator(g / "expected"))
      if (!prov["files"].contains(e.path().filename().string()))
        why.push_back(fmt::format("expected/{}: not listed in provenance.json", e.path().filename().string()));
  return why;
}

// Runs the scene into `out` (a fresh directory).
void run_into(const Scene& scene, const fs::path& out, const EngineFactory& make, int threads) {
  fs::remove_all(out);
  RunOptions options;
  options.make_engine = make;
  with_threads(threads, [&] {
    const RunResult r = run_scene(scene, options);
    write_outputs(r, out, "golden", threads, {});
  });
  fs::remove(out / "timings.csv");
  fs::remove(out / "manifest.json");
}

// The first difference between two texts, as "line N: expected ... got ...".
std::string first_difference(const std::string& expected, const std::string& got) {
  std::istringstream a(expected), b(got);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ha = static_cast<bool>(std::getline(a, la)), hb = static_cast<bool>(std::getline(b, lb));
    if (!ha && !hb) return "same lines, different bytes (line endings?)";
    if (ha != hb || la != lb) {
      auto cut = [](const std::string& s) { return s.size() > 120 ? s.substr(0, 117) + "..." : s; };
      return fmt::format("line {}: expected \"{}\", got \"{}\"", line, ha ? cut(la) : "<end of file>",
                         hb ? cut(lb) : "<end of file>");
    }
  }
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

}  // namespace

fs::path default_golden_dir() {
  if (fs::is_directory("data/golden")) return "data/golden";
  return data_dir() / "data" / "golden";
}

std::vector<GoldenResult> golden_check(const fs::path& dir, const EngineFactory& make, int threads) {
  std::vector<GoldenResult> results;
  const ScratchDir scratch("axonguide-golden");  // removed however this ends
  const fs::path& work = scratch.path();
  for (const fs::path& g : golden_networks(dir)) {
    GoldenResult r;
    r.name = g.filename().string();
    // A network that does not verify is refused: it fails with the reasons, unrun.
    r.differences = verify_network(g);
    if (!r.differences.empty()) {
      r.pass = false;
      r.verified = false;
      results.push_back(std::move(r));
      continue;
    }
    const Scene scene = load_scene_file((g / "scene.json").string()).scene;
    const fs::path out = work / r.name;
    run_into(scene, out, make, threads);
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(g / "expected")) names.push_back(e.path().filename().string());
    for (const auto& e : fs::directory_iterator(out)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    for (const auto& name : names) {
      const bool have_expected = fs::exists(g / "expected" / name), have_got = fs::exists(out / name);
      if (!have_expected || !have_got) {
        r.pass = false;
        r.differences.push_back(fmt::format("{}: {}", name, have_expected ? "not produced" : "not expected"));
        continue;
      }
      const std::string a = read_all(g / "expected" / name), b = read_all(out / name);
      if (a != b) {
        r.pass = false;
        r.differences.push_back(fmt::format("{}: {}", name, first_difference(a, b)));
      }
    }
    results.push_back(std::move(r));
  }
  return results;
}

std::vector<std::string> golden_bless(const fs::path& dir, const std::string& reason, int threads,
                                      const std::string& only) {
  if (reason.empty()) throw InputError("golden bless: --reason TEXT is required (it goes into CHANGELOG.md)");
  if (reason.find('\n') != std::string::npos || reason.find('\r') != std::string::npos)
    throw InputError("golden bless: --reason is one line (it becomes a line of CHANGELOG.md)");
  // Everything that can refuse does so before anything changes: every network to bless has a
  // scene that loads, and an expected/ that holds only the files its provenance lists.
  std::vector<std::pair<fs::path, Scene>> networks;
  for (const fs::path& g : golden_networks(dir)) {
    if (!only.empty() && g.filename().string() != only) continue;
    if (!fs::exists(g / "scene.json"))
      throw InputError(fmt::format("golden bless: {}/scene.json is missing (restore it from git, or remove the folder); "
                                   "nothing was changed",
                                   g.string()));
    networks.emplace_back(g, load_scene_file((g / "scene.json").string()).scene);
    if (fs::is_directory(g / "expected")) {
      json listed = json::object();
      try {
        listed = json::parse(read_all(g / "provenance.json")).at("files");
      } catch (const std::exception&) {
      }
      for (const auto& e : fs::directory_iterator(g / "expected"))
        if (!listed.is_object() || !listed.contains(e.path().filename().string()))
          throw InputError(fmt::format("golden bless: {}: not listed in provenance.json, and blessing replaces "
                                       "expected/; move it out first. Nothing was changed",
                                       e.path().string()));
    }
  }
  if (!only.empty() && networks.empty())
    throw InputError(fmt::format("golden bless: no golden network named '{}' under {}", only, dir.string()));
  std::vector<std::string> changed;
  std::string log;
  for (const auto& [g, scene] : networks) {
    const std::string name = g.filename().string();
    // Rendered beside expected/ in a folder of this process's own, then swapped in by
    // renames: expected/ is whole, old or new, at every instant.
    const ScratchDir fresh(".expected.new", g);
    run_into(scene, fresh.path() / "expected", {}, threads);
    json files = json::object();
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(fresh.path() / "expected")) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    bool differs = !fs::exists(g / "expected");
    for (const auto& f : names) {
      const std::string hash = sha256_file(fresh.path() / "expected" / f);
      files[f] = hash;
      const fs::path old = g / "expected" / f;
      const std::string old_hash = fs::exists(old) ? sha256_file(old) : "none";
      if (old_hash != hash) {
        differs = true;
        log += fmt::format("  - `{}/{}`: {} -> {}\n", name, f, old_hash.substr(0, 12), hash.substr(0, 12));
      }
    }
    if (fs::exists(g / "expected")) fs::rename(g / "expected", fresh.path() / "old");
    fs::rename(fresh.path() / "expected", g / "expected");
    json prov;
    prov["name"] = name;
    prov["seed"] = scene.seed;
    prov["scene"] = scene_to_json(scene);
    prov["version"] = kVersion;
    prov["commit"] = kCommit;
    prov["compiler"] = kCompiler;
    prov["build_type"] = kBuildType;
    prov["cxx_flags"] = kCxxFlags;
    prov["blessed"] = utc_now();
    prov["reason"] = reason;
    prov["threads"] = threads;
    prov["backend"] = "reference";
    prov["files"] = files;
    write_file_atomically(g, "provenance.json", prov.dump(2) + "\n");
    if (differs) changed.push_back(name);
  }
  // CHANGELOG.md: the old text and this entry, written whole under a temporary name.
  const std::string before = fs::exists(dir / "CHANGELOG.md") ? read_all(dir / "CHANGELOG.md") : std::string();
  write_file_atomically(
      dir, "CHANGELOG.md",
      before + fmt::format("\n## {} — commit {}\n\nReason: {}\n\n", utc_now(), kCommit, reason) +
          (changed.empty() ? "No expected output changed.\n" : fmt::format("Changed: {}\n\n{}", fmt::join(changed, ", "), log)));
  return changed;
}

}  // namespace axg::validate
