// Checkpoints: a flat little-endian stream of counted arrays, hashed as it is written.
// Every count is checked against the bytes left before anything is allocated, so a
// damaged file is an error and never a huge allocation.
#include "axonguide/checkpoint.hpp"

#include <signal.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <type_traits>

#include <fmt/format.h>

#include "axonguide/error.hpp"
#include "axonguide/fault.hpp"
#include "axonguide/output.hpp"
#include "axonguide/version.hpp"

namespace axg {

namespace fs = std::filesystem;

void fault_point(std::string_view name) {
  static const char* const at = std::getenv("AXG_FAULT_KILL_AT");
  if (at == nullptr || name != at) return;
  static const char* const sig = std::getenv("AXG_FAULT_SIGNAL");
  const std::string_view which = sig ? sig : "KILL";
  ::raise(which == "INT" ? SIGINT : which == "TERM" ? SIGTERM : which == "STOP" ? SIGSTOP : SIGKILL);
}

std::string scene_hash(const Scene& scene) { return sha256_hex(scene_to_json(scene).dump()); }

namespace {

constexpr char kMagic[8] = {'A', 'X', 'G', 'C', 'K', 'P', 'T', '1'};
constexpr std::uint32_t kByteOrder = 0x01020304;

static_assert(sizeof(core::Vec3) == 24 && std::is_trivially_copyable_v<core::Vec3>);
static_assert(sizeof(core::AxonStatus) == 1);

class Writer {
 public:
  explicit Writer(AtomicFile& f) : f_(f) {}
  void bytes(const void* p, std::size_t n) {
    const std::string_view s(static_cast<const char*>(p), n);
    hash_.update(s);
    f_.write(s);
    size_ += n;
  }
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  template <class T>
  void array(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    bytes(v.data(), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    pod<std::uint64_t>(s.size());
    bytes(s.data(), s.size());
  }
  std::uint64_t finish() {
    const std::string h = hash_.hex();
    f_.write(h);
    return size_ + h.size();
  }

 private:
  AtomicFile& f_;
  Sha256 hash_;
  std::uint64_t size_ = 0;
};

class Reader {
 public:
  Reader(const fs::path& path) : path_(path), in_(path, std::ios::binary) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (!in_ || ec) throw RunError(fmt::format("cannot read the checkpoint {}", path.string()));
    if (size < sizeof kMagic + 64) bad("shorter than its header");
    left_ = size - 64;
  }
  void bytes(void* p, std::size_t n) {
    if (n > left_) bad("truncated");
    in_.read(static_cast<char*>(p), static_cast<std::streamsize>(n));
    if (!in_) bad("truncated");
    hash_.update(std::string_view(static_cast<const char*>(p), n));
    left_ -= n;
  }
  template <class T>
  T pod() {
    T v;
    bytes(&v, sizeof v);
    return v;
  }
  template <class T>
  void array(std::vector<T>& v) {
    const auto n = pod<std::uint64_t>();
    if (n > left_ / sizeof(T)) bad("an array longer than the file");
    v.resize(n);
    bytes(v.data(), n * sizeof(T));
  }
  std::string text() {
    std::string s;
    const auto n = pod<std::uint64_t>();
    if (n > left_) bad("a string longer than the file");
    s.resize(n);
    bytes(s.data(), n);
    return s;
  }
  void finish() {
    if (left_ != 0) bad("bytes after its last field");
    std::string stored(64, '\0');
    in_.read(stored.data(), 64);
    if (!in_ || stored != hash_.hex()) bad("its SHA-256 does not match its contents");
  }
  [[noreturn]] void bad(const char* why) const {
    throw RunError(fmt::format("the checkpoint {} is damaged ({}); run again with --force to start over", path_.string(), why));
  }

 private:
  fs::path path_;
  std::ifstream in_;
  Sha256 hash_;
  std::uint64_t left_ = 0;
};

}  // namespace

std::uint64_t write_checkpoint(const fs::path& dir, const RunResult& r, std::uint32_t step, const EngineState& e) {
  AtomicFile f(dir, kCheckpointName);
  Writer w(f);
  w.bytes(kMagic, sizeof kMagic);
  w.pod(kByteOrder);
  w.text(kVersion);
  w.text(kCommit);
  w.text(scene_hash(r.scene));
  w.pod(step);
  // What the run has recorded.
  w.array(r.soma);
  w.pod(r.placement_redraws);
  w.pod<std::uint64_t>(r.stats.size());
  for (const StepStats& s : r.stats) {
    w.pod(s.step);
    w.pod(s.growing);
    w.pod(s.connected);
    w.pod(s.exited);
    w.pod(s.particles);
  }
  w.pod<std::uint64_t>(r.paths.size());
  for (const auto& p : r.paths) w.array(p);
  w.pod<std::uint64_t>(r.frames.size());
  for (const ParticleFrame& fr : r.frames) {
    w.pod(fr.step);
    w.pod(fr.count);
    w.pod(fr.stride);
    w.array(fr.pos);
    w.array(fr.cue);
  }
  w.pod<std::uint64_t>(r.times.rows().size());
  for (const auto& row : r.times.rows()) {
    w.pod(row.step);
    w.text(row.phase);
    w.pod(row.seconds);
  }
  // The engine.
  w.array(e.axons.tip);
  w.array(e.axons.length);
  w.array(e.axons.status);
  w.array(e.axons.steps);
  w.array(e.axons.target);
  w.array(e.heading);
  w.array(e.step_length);
  w.pod(e.connected);
  w.pod(e.exited);
  w.pod(e.next_particle_id);
  w.array(e.particle_pos);
  w.array(e.particle_vel);
  w.array(e.particle_id);
  w.array(e.particle_cue);
  w.array(e.grid);
  const std::uint64_t size = w.finish();
  fault_point(fmt::format("checkpoint {}", step));
  f.commit();
  return size;
}

RunCheckpoint read_checkpoint(const fs::path& path) {
  Reader in(path);
  char magic[sizeof kMagic];
  in.bytes(magic, sizeof magic);
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) in.bad("not an axonguide checkpoint");
  if (in.pod<std::uint32_t>() != kByteOrder) in.bad("written on a machine of another byte order");
  RunCheckpoint c;
  c.version = in.text();
  c.commit = in.text();
  c.scene_hash = in.text();
  c.step = in.pod<std::uint32_t>();
  RunResult& r = c.progress;
  r.steps_run = c.step;
  in.array(r.soma);
  r.placement_redraws = in.pod<std::uint64_t>();
  const auto stats = in.pod<std::uint64_t>();
  if (stats > (std::uint64_t{1} << 33)) in.bad("an impossible number of steps");
  for (std::uint64_t k = 0; k < stats; ++k) {
    StepStats s;
    s.step = in.pod<std::uint32_t>();
    s.growing = in.pod<std::uint64_t>();
    s.connected = in.pod<std::uint64_t>();
    s.exited = in.pod<std::uint64_t>();
    s.particles = in.pod<std::uint64_t>();
    r.stats.push_back(s);
  }
  const auto paths = in.pod<std::uint64_t>();
  if (paths > stats) in.bad("more path rows than steps");
  r.paths.resize(paths);
  for (auto& p : r.paths) in.array(p);
  const auto frames = in.pod<std::uint64_t>();
  if (frames > stats) in.bad("more particle frames than steps");
  r.frames.resize(frames);
  for (ParticleFrame& fr : r.frames) {
    fr.step = in.pod<std::uint32_t>();
    fr.count = in.pod<std::uint64_t>();
    fr.stride = in.pod<std::uint32_t>();
    in.array(fr.pos);
    in.array(fr.cue);
  }
  const auto rows = in.pod<std::uint64_t>();
  for (std::uint64_t k = 0; k < rows; ++k) {
    const auto step = in.pod<std::uint32_t>();
    const std::string phase = in.text();
    const auto seconds = in.pod<double>();
    r.times.rows().push_back({step, phase, seconds});
  }
  EngineState& e = c.engine;
  in.array(e.axons.tip);
  in.array(e.axons.length);
  in.array(e.axons.status);
  in.array(e.axons.steps);
  in.array(e.axons.target);
  in.array(e.heading);
  in.array(e.step_length);
  e.connected = in.pod<std::uint64_t>();
  e.exited = in.pod<std::uint64_t>();
  e.next_particle_id = in.pod<std::uint64_t>();
  in.array(e.particle_pos);
  in.array(e.particle_vel);
  in.array(e.particle_id);
  in.array(e.particle_cue);
  in.array(e.grid);
  in.finish();
  const std::size_t n = r.soma.size();
  if (e.axons.tip.size() != n || e.axons.length.size() != n || e.axons.status.size() != n ||
      e.axons.steps.size() != n || e.axons.target.size() != n || e.heading.size() != n)
    in.bad("per-neuron arrays of different lengths");
  return c;
}

}  // namespace axg
