#include "axonguide/study/sweep.hpp"

#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <mutex>
#include <sstream>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "axonguide/study/assay.hpp"
#include "axonguide/core/pmath.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/fault.hpp"
#include "axonguide/scene/json_input.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/version.hpp"

namespace axg::sweep {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

[[noreturn]] void bad(const std::string& origin, const std::string& what) {
  throw InputError(fmt::format("sweep {}: {}", origin, what));
}

std::vector<std::string> split_path(const std::string& key) {
  std::vector<std::string> parts;
  std::string cur;
  for (char c : key) {
    if (c == '.') {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(cur);
  return parts;
}

bool is_index(const std::string& s) {
  if (s.empty() || s.size() > 9) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// Sets key (dotted, "*" for every array element) to value in j, creating objects on the way.
void set_path(json& j, const std::vector<std::string>& parts, std::size_t at, const json& value,
              const std::string& key) {
  if (at == parts.size()) {
    j = value;
    return;
  }
  const std::string& p = parts[at];
  if (p == "*") {
    if (!j.is_array() || j.empty())
      throw InputError(fmt::format("sweep: key {}: \"*\" needs a non-empty array in the base scene", key));
    for (auto& e : j) set_path(e, parts, at + 1, value, key);
    return;
  }
  if (j.is_array()) {
    if (!is_index(p) || std::stoul(p) >= j.size())
      throw InputError(fmt::format("sweep: key {}: \"{}\" must index the base scene's array of {} (0 to {})", key, p,
                                   j.size(), j.size() - 1));
    set_path(j[std::stoul(p)], parts, at + 1, value, key);
    return;
  }
  if (j.is_null()) j = json::object();
  if (!j.is_object())
    throw InputError(fmt::format("sweep: key {}: \"{}\" descends into a value that is not an object", key, p));
  set_path(j[p], parts, at + 1, value, key);
}

// Whether two key paths reach one part of a scene: one is the other or lies inside it, "*"
// standing for any index.
bool paths_overlap(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    if (a[i] != b[i] && a[i] != "*" && b[i] != "*") return false;
  return true;
}

std::vector<json> read_values(const json& v, const std::string& origin, const std::string& path) {
  std::vector<json> out;
  if (v.contains("values")) {
    const json& vals = v["values"];
    if (!vals.is_array() || vals.empty()) bad(origin, path + ".values must be a non-empty array");
    for (const auto& x : vals) out.push_back(x);
    return out;
  }
  for (const char* kind : {"log", "linear"}) {
    if (!v.contains(kind)) continue;
    const json& r = v[kind];
    if (!r.is_object() || !r.contains("from") || !r.contains("to") || !r.contains("count") ||
        !r["from"].is_number() || !r["to"].is_number() || !r["count"].is_number_unsigned())
      bad(origin, fmt::format("{}.{} must be {{\"from\": number, \"to\": number, \"count\": integer >= 1}}", path, kind));
    const double a = r["from"].get<double>(), b = r["to"].get<double>();
    const std::uint64_t n = r["count"].get<std::uint64_t>();
    if (n < 1 || n > 100000) bad(origin, path + "." + kind + ".count must be in [1, 100000]");
    const bool log = std::string(kind) == "log";
    if (log && !(a > 0 && b > 0)) bad(origin, path + ".log: from and to must be > 0");
    // Portable log/exp: the same grid on every machine.
    const double la = log ? core::pm::log(a) : a, lb = log ? core::pm::log(b) : b;
    // The ends are exact: the first value is `from` (the only one when count is 1), the
    // last is `to`.
    for (std::uint64_t k = 0; k < n; ++k) {
      const double t = n == 1 ? 0.0 : static_cast<double>(k) / static_cast<double>(n - 1);
      double x = k + 1 == n ? lb : la + (lb - la) * t;
      x = k == 0 ? a : (k + 1 == n ? b : (log ? core::pm::exp(x) : x));
      if (!std::isfinite(x))
        bad(origin, fmt::format("{}.{}: the value at {} of {} is not a finite number (from {} to {})", path, kind, k, n,
                                a, b));
      out.push_back(x);
    }
    return out;
  }
  bad(origin, path + " needs \"values\": [...], \"log\": {from, to, count} or \"linear\": {from, to, count}");
}

std::string cell(double v) { return std::isfinite(v) ? fmt::format("{}", v) : std::string(); }

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out + "\"";
}

std::string value_text(const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }


bool run_folder_verifies(const fs::path& dir) {
  std::ifstream in(dir / "manifest.json");
  if (!in) return false;
  try {
    const json m = json::parse(in);
    for (const auto& [name, entry] : m.at("files").items())
      if (name != "timings.csv" && sha256_file(dir / name) != entry.at("sha256").get<std::string>()) return false;
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

Spec parse_spec(const json& j, const std::string& origin, const fs::path& folder) {
  if (!j.is_object()) bad(origin, "must be a JSON object {scene, parameters, seeds, outputs}");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "scene" && it.key() != "parameters" && it.key() != "seeds" && it.key() != "mode" &&
        it.key() != "outputs" && it.key() != "description")
      bad(origin, fmt::format("unknown key {} (allowed: scene, parameters, mode, seeds, outputs, description)", it.key()));
  Spec s;
  if (!j.contains("scene")) bad(origin, "needs \"scene\": a scene file path or an inline scene object");
  const json& scene = j["scene"];
  if (scene.is_string()) {
    if (scene.get<std::string>().find('\0') != std::string::npos)
      bad(origin, "scene: a NUL byte in a path (it would cut the path short)");
    fs::path p = scene.get<std::string>();
    if (p.is_relative()) p = folder / p;
    // A scene file: duplicate keys and trailing bytes are refused as parse_scene refuses them.
    s.base = parse_json_strict(read_input_file(p.string(), fmt::format("sweep {}: scene", origin)),
                               fmt::format("sweep {}: scene {}", origin, p.string()));
    s.base_origin = p.string();
  } else if (scene.is_object()) {
    s.base = scene;
    s.base_origin = origin + " (inline scene)";
  } else {
    bad(origin, "scene must be a file path or an object");
  }
  // The base must be a valid scene on its own.
  parse_scene(s.base.dump(), s.base_origin);

  if (j.contains("mode")) {
    if (j["mode"] == "grid") s.zip = false;
    else if (j["mode"] == "zip") s.zip = true;
    else bad(origin, "mode must be \"grid\" (every combination) or \"zip\" (the i-th value of each parameter)");
  }
  if (j.contains("parameters")) {
    const json& ps = j["parameters"];
    if (!ps.is_array()) bad(origin, "parameters must be an array");
    for (std::size_t k = 0; k < ps.size(); ++k) {
      const std::string path = fmt::format("parameters[{}]", k);
      const json& p = ps[k];
      if (!p.is_object()) bad(origin, path + " must be an object {key or keys, values | log | linear, name}");
      for (auto it = p.begin(); it != p.end(); ++it)
        if (it.key() != "key" && it.key() != "keys" && it.key() != "values" && it.key() != "log" &&
            it.key() != "linear" && it.key() != "name" && it.key() != "cases")
          bad(origin, fmt::format("{}: unknown key {} (allowed: key, keys, values, log, linear, name, cases)", path,
                                  it.key()));
      if (p.contains("name") && !p["name"].is_string()) bad(origin, path + ".name must be a string");
      const int sources = static_cast<int>(p.contains("values")) + static_cast<int>(p.contains("log")) +
                          static_cast<int>(p.contains("linear")) + static_cast<int>(p.contains("cases"));
      if (sources > 1) bad(origin, path + ": give one of \"values\", \"log\", \"linear\" and \"cases\"");
      Parameter par;
      if (p.contains("cases")) {
        const json& cs = p["cases"];
        if (!cs.is_object() || cs.empty() || !p.contains("name"))
          bad(origin, path + ": \"cases\" must be a non-empty object {label: {key: value, ...}} with a \"name\"");
        if (p.contains("key") || p.contains("keys"))
          bad(origin, path + ": \"cases\" name their keys inside each case, not in \"key\" or \"keys\"");
        par.name = p["name"].get<std::string>();
        for (auto it = cs.begin(); it != cs.end(); ++it) {
          if (!it.value().is_object()) bad(origin, path + ".cases." + it.key() + " must be an object {key: value}");
          for (auto kv = it.value().begin(); kv != it.value().end(); ++kv)
            if (kv.key() == "seed") bad(origin, path + ".cases." + it.key() + ": the seed is swept by \"seeds\"");
          par.values.push_back(it.key());
          par.cases.push_back(it.value());
        }
        s.parameters.push_back(std::move(par));
        continue;
      }
      if (p.contains("key") && p.contains("keys")) bad(origin, path + ": give \"key\" or \"keys\", not both");
      if (p.contains("key")) {
        if (!p["key"].is_string()) bad(origin, path + ".key must be a string \"a.b.c\"");
        par.keys.push_back(p["key"].get<std::string>());
      }
      if (p.contains("keys")) {
        if (!p["keys"].is_array()) bad(origin, path + ".keys must be an array of strings");
        for (std::size_t i = 0; i < p["keys"].size(); ++i) {
          if (!p["keys"][i].is_string()) bad(origin, fmt::format("{}.keys[{}] must be a string \"a.b.c\"", path, i));
          par.keys.push_back(p["keys"][i].get<std::string>());
        }
      }
      if (par.keys.empty()) bad(origin, path + " needs \"key\": \"a.b.c\" or \"keys\": [...]");
      for (const auto& key : par.keys)
        if (key == "seed") bad(origin, path + ": the seed is swept by \"seeds\", not as a parameter");
      par.name = p.contains("name") ? p["name"].get<std::string>() : par.keys[0];
      par.values = read_values(p, origin, path);
      s.parameters.push_back(std::move(par));
    }
    // One parameter per part of the scene, and one column per name: a key that two
    // parameters set (or one sets inside what another sets: cues.sources.0 and
    // cues.sources.*.kd) would run one value under two labels.
    std::set<std::string> names;
    std::vector<std::pair<std::string, std::string>> set_by;  // (key, parameter)
    for (const Parameter& par : s.parameters) {
      if (!names.insert(par.name).second) bad(origin, fmt::format("two parameters are named {}", par.name));
      std::set<std::string> keys(par.keys.begin(), par.keys.end());
      for (const json& c : par.cases)
        for (auto kv = c.begin(); kv != c.end(); ++kv) keys.insert(kv.key());
      for (const std::string& key : keys)
        for (const auto& [other, by] : set_by)
          if (by != par.name && paths_overlap(split_path(key), split_path(other)))
            bad(origin, fmt::format("key {} of parameter {} and key {} of parameter {} set the same part of the scene",
                                    other, by, key, par.name));
      for (const std::string& key : keys) set_by.emplace_back(key, par.name);
    }
    if (s.zip)
      for (const auto& par : s.parameters)
        if (par.values.size() != s.parameters[0].values.size())
          bad(origin, fmt::format("mode \"zip\": parameter {} has {} values, {} has {}", par.name, par.values.size(),
                                  s.parameters[0].name, s.parameters[0].values.size()));
  }
  if (!j.contains("seeds")) {
    s.seeds = {1};
  } else if (j["seeds"].is_number_unsigned()) {
    const std::uint64_t n = j["seeds"].get<std::uint64_t>();
    if (n < 1 || n > 1000000) bad(origin, "seeds must be a count in [1, 1000000] or a list of seeds");
    for (std::uint64_t k = 1; k <= n; ++k) s.seeds.push_back(k);
  } else if (j["seeds"].is_array() && !j["seeds"].empty()) {
    std::set<std::uint64_t> seen;
    for (const auto& x : j["seeds"]) {
      if (!x.is_number_unsigned()) bad(origin, "seeds: every seed must be an unsigned integer");
      if (!seen.insert(x.get<std::uint64_t>()).second)
        bad(origin, fmt::format("seeds: {} is given twice (a repeated seed repeats its run, and narrows the intervals "
                                "without new data)",
                                x.get<std::uint64_t>()));
      s.seeds.push_back(x.get<std::uint64_t>());
    }
  } else {
    bad(origin, "seeds must be a count in [1, 1000000] or a non-empty list of seeds");
  }
  if (j.contains("outputs")) {
    if (j["outputs"] == "metrics") s.write_runs = false;
    else if (j["outputs"] == "runs") s.write_runs = true;
    else bad(origin, "outputs must be \"metrics\" (records only) or \"runs\" (also each member's run folder)");
  }
  // The member count, multiplied with a bound (a product of large counts wraps to 0).
  constexpr std::uint64_t kMaxMembers = 10000000;
  std::uint64_t members = s.seeds.size();
  for (std::size_t k = 0; k < s.parameters.size() && !(s.zip && k > 0); ++k) {
    const std::uint64_t n = s.parameters[k].values.size();  // >= 1
    if (members > kMaxMembers / n) {
      members = kMaxMembers + 1;
      break;
    }
    members *= n;
  }
  if (members > kMaxMembers) bad(origin, "more than 10^7 members (points x seeds): at most 10^7");
  // Every point must make a valid scene: check them before anything runs.
  for (std::size_t p = 0; p < point_count(s); ++p) {
    try {
      parse_scene(member_scene_json(s, p * s.seeds.size()).dump(), fmt::format("{} point {}", origin, p));
    } catch (const InputError& e) {
      const std::vector<json> values = point_values(s, p);
      std::string where;
      for (std::size_t k = 0; k < s.parameters.size(); ++k)
        where += fmt::format("{}{}={}", k ? ", " : "", s.parameters[k].name, value_text(values[k]));
      throw InputError(fmt::format("sweep {}: point {} ({}): {}", origin, p, where, e.what()));
    }
  }
  return s;
}

Spec load_spec(const std::string& path) {
  try {
    const json j = parse_json_strict(read_input_file(path, "sweep"), fmt::format("sweep {}", path));
    return parse_spec(j, path, fs::path(path).parent_path());
  } catch (const InputError& e) {
    throw InputError(printable(e.what()));  // messages quote keys and values of the files
  }
}

std::size_t point_count(const Spec& spec) {
  if (spec.parameters.empty()) return 1;
  if (spec.zip) return spec.parameters[0].values.size();
  std::size_t n = 1;
  for (const auto& p : spec.parameters) n *= p.values.size();
  return n;
}

std::size_t member_count(const Spec& spec) { return point_count(spec) * spec.seeds.size(); }

std::vector<json> point_values(const Spec& spec, std::size_t point) {
  std::vector<json> out(spec.parameters.size());
  std::size_t rest = point;
  for (std::size_t k = spec.parameters.size(); k-- > 0;) {
    const auto& vals = spec.parameters[k].values;
    out[k] = spec.zip ? vals[point] : vals[rest % vals.size()];
    if (!spec.zip) rest /= vals.size();
  }
  return out;
}

json member_scene_json(const Spec& spec, std::size_t member) {
  json scene = spec.base;
  const std::size_t point = member / spec.seeds.size();
  const auto values = point_values(spec, point);
  for (std::size_t k = 0; k < spec.parameters.size(); ++k) {
    const Parameter& par = spec.parameters[k];
    if (!par.cases.empty()) {
      std::size_t c = 0;
      while (par.values[c] != values[k]) ++c;
      for (const auto& [key, value] : par.cases[c].items()) set_path(scene, split_path(key), 0, value, key);
      continue;
    }
    for (const auto& key : par.keys) set_path(scene, split_path(key), 0, values[k], key);
  }
  scene["seed"] = spec.seeds[member % spec.seeds.size()];
  return scene;
}

MemberResult run_member(const Spec& spec, std::size_t member, const RunOptions& options, const fs::path& run_dir,
                        const std::string& backend) {
  fault_point(fmt::format("sweep member {}", member));
  MemberResult r;
  r.member = member;
  try {
    const ParseResult parsed = parse_scene(member_scene_json(spec, member).dump(), fmt::format("member {}", member));
    r.scene_sha256 = sha256_hex(scene_to_json(parsed.scene).dump());
    RunResult run = run_scene(parsed.scene, options);
    r.metrics = assay::scalar_metrics(assay::measure(run.scene, run.soma, run.neurons, assay::reference_cues(run.scene)));
    r.connections_sha256 = sha256_hex(connections_csv(run));
    if (!run_dir.empty()) write_outputs(run, run_dir, backend, 1, parsed.warnings);
    r.ok = true;
  } catch (const InputError& e) {
    r.exit_code = kExitBadInput;
    r.message = e.what();
  } catch (const RunError& e) {
    r.exit_code = kExitCannotRun;
    r.message = e.what();
  } catch (const std::bad_alloc&) {
    r.exit_code = kExitCannotRun;
    r.message = "out of memory";
  } catch (const Interrupted&) {
    throw;  // a stop asked for (Ctrl-C from Python): not this member's failure
  } catch (const std::exception& e) {
    r.exit_code = kExitCannotRun;
    r.message = e.what();
  }
  if (!r.ok) {
    for (const auto& name : assay::scalar_metric_names()) r.metrics.emplace_back(name, kNaN);
    if (r.scene_sha256.empty()) r.scene_sha256 = sha256_hex(member_scene_json(spec, member).dump());
  }
  return r;
}

json record_json(const MemberResult& r, std::uint64_t seed) {
  json metrics = json::object();
  for (const auto& [name, value] : r.metrics) metrics[name] = std::isfinite(value) ? json(value) : json(nullptr);
  json j = {{"member", r.member},         {"seed", seed},
            {"version", kVersion},        {"scene_sha256", r.scene_sha256},
            {"status", r.ok ? "ok" : "failed"}, {"exit_code", r.exit_code},
            {"message", r.message},       {"metrics", metrics},
            {"connections_sha256", r.connections_sha256}};
  return j;
}

MemberResult result_from_record(const json& j) {
  MemberResult r;
  r.member = j.at("member").get<std::size_t>();
  r.ok = j.at("status") == "ok";
  r.exit_code = j.at("exit_code").get<int>();
  r.message = j.at("message").get<std::string>();
  r.scene_sha256 = j.at("scene_sha256").get<std::string>();
  r.connections_sha256 = j.at("connections_sha256").get<std::string>();
  for (const auto& name : assay::scalar_metric_names()) {
    const json& v = j.at("metrics").at(name);
    r.metrics.emplace_back(name, v.is_null() ? kNaN : v.get<double>());
  }
  return r;
}

fs::path record_path(const fs::path& dir, std::size_t member) {
  return dir / "members" / fmt::format("m{:07d}.json", member);
}

std::optional<MemberResult> read_verified_record(const Spec& spec, const fs::path& dir, std::size_t member) {
  std::ifstream in(record_path(dir, member));
  if (!in) return std::nullopt;
  try {
    json j = json::parse(in);
    const std::string stored = j.at("record_sha256").get<std::string>();
    j.erase("record_sha256");
    if (sha256_hex(j.dump()) != stored) return std::nullopt;
    if (j.at("version") != kVersion || j.at("member") != member || j.at("status") != "ok") return std::nullopt;
    const ParseResult parsed = parse_scene(member_scene_json(spec, member).dump(), "member");
    if (j.at("scene_sha256") != sha256_hex(scene_to_json(parsed.scene).dump())) return std::nullopt;
    if (spec.write_runs && !run_folder_verifies(dir / "members" / fmt::format("m{:07d}", member))) return std::nullopt;
    MemberResult r = result_from_record(j);
    r.skipped = true;
    return r;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

MeanSe mean_se(const std::vector<double>& xs) {
  MeanSe c{0, kNaN, kNaN};
  double sum = 0;
  for (double x : xs)
    if (std::isfinite(x)) {
      sum += x;
      ++c.n;
    }
  if (c.n == 0) return c;
  const double n = static_cast<double>(c.n);
  c.mean = sum / n;
  if (c.n < 2) return c;
  double ss = 0;
  for (double x : xs)
    if (std::isfinite(x)) ss += (x - c.mean) * (x - c.mean);
  c.se = std::sqrt(ss / (n - 1.0) / n);
  return c;
}

MeanCi mean_ci(const std::vector<double>& xs) {
  const MeanSe m = mean_se(xs);
  MeanCi c{m.n, m.mean, kNaN, kNaN};
  if (m.n < 2) return c;
  const double half = gsl_cdf_tdist_Pinv(0.975, static_cast<double>(m.n) - 1.0) * m.se;
  c.low = c.mean - half;
  c.high = c.mean + half;
  return c;
}

std::vector<MemberResult> run_in_memory(const std::vector<Spec>& specs, int threads, const RunOptions& options) {
  std::vector<std::size_t> first{0};
  for (const Spec& s : specs) first.push_back(first.back() + member_count(s));
  std::vector<MemberResult> out(first.back());
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, out.size(), [&](std::size_t k) {
      const std::size_t s = static_cast<std::size_t>(std::upper_bound(first.begin(), first.end(), k) - first.begin()) - 1;
      out[k] = run_member(specs[s], k - first[s], options);
    });
  });
  return out;
}

double metric(const MemberResult& r, const std::string& name) {
  for (const auto& [n, v] : r.metrics)
    if (n == name) return v;
  throw std::invalid_argument("sweep::metric: no metric named " + name);
}

namespace {

// Removes the temporary records (".mNNNNNNN.json.tmp-PID") of sweeps that were killed while
// they wrote them; a live process's (another sweep writing this folder now) are left.
void remove_killed_temporaries(const fs::path& members) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(members, ec)) {
    const std::optional<TemporaryName> t = parse_temporary_name(e.path().filename().string());
    if (!t || t->name.rfind('m', 0) != 0 || t->name.size() < 5 || t->name.substr(t->name.size() - 5) != ".json")
      continue;
    if (::kill(static_cast<pid_t>(t->pid), 0) == 0 || errno == EPERM) continue;  // alive
    stale.push_back(e.path());
  }
  for (const fs::path& p : stale) fs::remove(p, ec);
}

}  // namespace

Outcome run(const Spec& spec, const fs::path& dir, const Options& options) {
  prepare_output_dir(dir);
  prepare_output_dir(dir / "members");
  remove_killed_temporaries(dir / "members");
  const std::size_t total = member_count(spec);
  Outcome out;
  out.members.resize(total);
  std::vector<std::size_t> pending;
  for (std::size_t m = 0; m < total; ++m) {
    if (auto rec = read_verified_record(spec, dir, m)) {
      out.members[m] = *rec;
      ++out.skipped;
    } else {
      pending.push_back(m);
    }
  }
  std::mutex mu;
  std::size_t done = out.skipped, failed = 0;
  if (options.on_member) options.on_member(done, total, failed, out.skipped);
  // Each result is recorded as it arrives, so that a sweep stopped at any point keeps
  // every member it finished.
  const Record record = [&](MemberResult r) {
    const std::size_t m = r.member;
    json rec = record_json(r, spec.seeds[m % spec.seeds.size()]);
    rec["record_sha256"] = sha256_hex(rec.dump());
    write_file_atomically(dir / "members", record_path(dir, m).filename().string(), rec.dump(1) + "\n");
    std::lock_guard<std::mutex> lock(mu);
    out.members[m] = std::move(r);
    ++done;
    if (!out.members[m].ok) ++failed;
    if (options.on_member) options.on_member(done, total, failed, out.skipped);
  };
  if (options.execute) {
    options.execute(pending, record);
  } else {
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    arena.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, pending.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
              const std::size_t m = pending[k];
              const fs::path run_dir = spec.write_runs ? dir / "members" / fmt::format("m{:07d}", m) : fs::path();
              record(run_member(spec, m, options.run, run_dir, options.backend));
            }
          },
          tbb::simple_partitioner());
    });
  }
  out.failed = failed;

  // Gather, in member order.
  const auto& names = assay::scalar_metric_names();
  std::string params_header;
  for (const auto& p : spec.parameters) params_header += fmt::format(",{}", csv_quote(p.name));
  {
    std::string text = "member,point" + params_header + ",seed,status,exit_code";
    for (const auto& n : names) text += fmt::format(",{}", n);
    text += ",connections_sha256,message\n";
    for (std::size_t m = 0; m < total; ++m) {
      const MemberResult& r = out.members[m];
      const std::size_t point = m / spec.seeds.size();
      text += fmt::format("{},{}", m, point);
      for (const auto& v : point_values(spec, point)) text += fmt::format(",{}", csv_quote(value_text(v)));
      text += fmt::format(",{},{},{}", spec.seeds[m % spec.seeds.size()], r.ok ? "ok" : "failed", r.exit_code);
      for (const auto& [name, value] : r.metrics) text += fmt::format(",{}", cell(value));
      text += fmt::format(",{},{}\n", r.connections_sha256, csv_quote(r.message));
    }
    write_file_atomically(dir, "sweep.csv", text);
  }
  {
    std::string text = "point" + params_header + ",members,ok,failed";
    for (const auto& n : names) text += fmt::format(",{0}_mean,{0}_ci_low,{0}_ci_high", n);
    text += "\n";
    const std::size_t S = spec.seeds.size();
    for (std::size_t p = 0; p < point_count(spec); ++p) {
      std::size_t ok = 0;
      for (std::size_t s = 0; s < S; ++s) ok += out.members[p * S + s].ok;
      text += fmt::format("{}", p);
      for (const auto& v : point_values(spec, p)) text += fmt::format(",{}", csv_quote(value_text(v)));
      text += fmt::format(",{},{},{}", S, ok, S - ok);
      for (std::size_t k = 0; k < names.size(); ++k) {
        std::vector<double> xs;
        for (std::size_t s = 0; s < S; ++s)
          if (out.members[p * S + s].ok) xs.push_back(out.members[p * S + s].metrics[k].second);
        const MeanCi c = mean_ci(xs);
        text += fmt::format(",{},{},{}", cell(c.mean), cell(c.low), cell(c.high));
      }
      text += "\n";
    }
    write_file_atomically(dir, "summary.csv", text);
  }
  {
    json canon;
    canon["scene"] = scene_to_json(parse_scene(spec.base.dump(), spec.base_origin).scene);
    canon["base_as_written"] = spec.base;
    json ps = json::array();
    for (const auto& p : spec.parameters) {
      json entry = {{"name", p.name}, {"keys", p.keys}, {"values", p.values}};
      if (!p.cases.empty()) entry["cases"] = p.cases;
      ps.push_back(entry);
    }
    canon["parameters"] = ps;
    canon["mode"] = spec.zip ? "zip" : "grid";
    canon["seeds"] = spec.seeds;
    canon["outputs"] = spec.write_runs ? "runs" : "metrics";
    canon["version"] = kVersion;
    canon["members"] = total;
    write_file_atomically(dir, "sweep.json", canon.dump(2) + "\n");
  }
  return out;
}

}  // namespace axg::sweep
