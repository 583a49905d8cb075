// Checkpoints: a flat little-endian stream of counted arrays, hashed as it is written.
// Every count is checked against the bytes left before anything is allocated, so a
// damaged file is an error and never a huge allocation.
#include "axonguide/engine/checkpoint.hpp"


#include <cstdlib>
#include <cstring>
#include <fstream>
#include <type_traits>

#include <fmt/format.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/fault.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/version.hpp"

namespace axg {

namespace fs = std::filesystem;

std::string scene_hash(const Scene& scene) { return sha256_hex(scene_to_json(scene).dump()); }

namespace {

// Format 2 added the sums of the open decision interval (EngineState::guidance); format 3
// the arbours (EngineState::arbour); format 4 the growth cones' own decision sums (cue
// steering of arbours); format 5 keeps those sums by cone index rather than by growing
// cone (morphology::Arbour::sums, shared by both engines).
constexpr char kMagic[8] = {'A', 'X', 'G', 'C', 'K', 'P', 'T', '5'};
constexpr char kMagicFormat1[8] = {'A', 'X', 'G', 'C', 'K', 'P', 'T', '1'};
constexpr char kMagicFormat2[8] = {'A', 'X', 'G', 'C', 'K', 'P', 'T', '2'};
constexpr char kMagicFormat3[8] = {'A', 'X', 'G', 'C', 'K', 'P', 'T', '3'};
constexpr char kMagicFormat4[8] = {'A', 'X', 'G', 'C', 'K', 'P', 'T', '4'};
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
  // A counted list; `fields` writes one element (min_bytes is the reader's bound).
  template <class T, class Fields>
  void list(const std::vector<T>& v, std::size_t /*min_bytes*/, Fields fields) {
    pod<std::uint64_t>(v.size());
    for (const T& x : v) fields(*this, x);
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
  void pod(T& v) {
    bytes(&v, sizeof v);
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
    text(s);
    return s;
  }
  void text(std::string& s) {
    const auto n = pod<std::uint64_t>();
    if (n > left_) bad("a string longer than the file");
    s.resize(n);
    bytes(s.data(), n);
  }
  // A counted list of elements of at least min_bytes each; `fields` reads one element.
  template <class T, class Fields>
  void list(std::vector<T>& v, std::size_t min_bytes, Fields fields) {
    const auto n = pod<std::uint64_t>();
    if (n > left_ / min_bytes) bad("a list longer than the file");
    v.resize(n);
    for (T& x : v) fields(*this, x);
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

// What follows the header, listed once for the writer and the reader (Run and State are
// const when writing).
template <class Io, class Run, class State>
void contents(Io& io, Run& r, State& e) {
  io.array(r.soma);
  io.pod(r.placement_redraws);
  io.list(r.stats, 36, [](auto& f, auto& s) {
    f.pod(s.step);
    f.pod(s.growing);
    f.pod(s.connected);
    f.pod(s.exited);
    f.pod(s.particles);
  });
  io.list(r.paths, 8, [](auto& f, auto& p) { f.array(p); });
  io.list(r.frames, 32, [](auto& f, auto& fr) {
    f.pod(fr.step);
    f.pod(fr.count);
    f.pod(fr.stride);
    f.array(fr.pos);
    f.array(fr.cue);
  });
  io.list(r.times.rows(), 20, [](auto& f, auto& row) {
    f.pod(row.step);
    f.text(row.phase);
    f.pod(row.seconds);
  });
  io.array(e.axons.tip);
  io.array(e.axons.length);
  io.array(e.axons.status);
  io.array(e.axons.steps);
  io.array(e.axons.target);
  io.array(e.heading);
  io.array(e.step_length);
  io.pod(e.connected);
  io.pod(e.exited);
  io.pod(e.next_particle_id);
  io.array(e.particle_pos);
  io.array(e.particle_vel);
  io.array(e.particle_id);
  io.array(e.particle_cue);
  io.array(e.grid);
  io.array(e.signal);
  io.array(e.receptors);
  io.array(e.guidance);
  io.array(e.arbour);
}

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
  contents(w, r, e);
  const std::uint64_t size = w.finish();
  fault_point(fmt::format("checkpoint {}", step));
  f.commit();
  return size;
}

RunCheckpoint read_checkpoint(const fs::path& path) {
  Reader in(path);
  char magic[sizeof kMagic];
  in.bytes(magic, sizeof magic);
  int earlier = 0;
  for (const auto& [old, format] : {std::pair{kMagicFormat1, 1}, std::pair{kMagicFormat2, 2}, std::pair{kMagicFormat3, 3},
                                    std::pair{kMagicFormat4, 4}})
    if (std::memcmp(magic, old, sizeof kMagic) == 0) earlier = format;
  if (earlier)
    throw RunError(fmt::format("the checkpoint {} was written by an earlier version of axonguide (checkpoint format {}); "
                               "this version cannot resume it: run again with --force to start over",
                               path.string(), earlier));
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) in.bad("not an axonguide checkpoint");
  if (in.pod<std::uint32_t>() != kByteOrder) in.bad("written on a machine of another byte order");
  RunCheckpoint c;
  c.version = in.text();
  c.commit = in.text();
  c.scene_hash = in.text();
  c.step = in.pod<std::uint32_t>();
  RunResult& r = c.progress;
  r.steps_run = c.step;
  EngineState& e = c.engine;
  contents(in, r, e);
  if (r.paths.size() > r.stats.size()) in.bad("more path rows than steps");
  if (r.frames.size() > r.stats.size()) in.bad("more particle frames than steps");
  in.finish();
  const std::size_t n = r.soma.size();
  if (e.axons.tip.size() != n || e.axons.length.size() != n || e.axons.status.size() != n ||
      e.axons.steps.size() != n || e.axons.target.size() != n || e.heading.size() != n)
    in.bad("per-neuron arrays of different lengths");
  const std::size_t particles = e.particle_pos.size();
  if (e.particle_id.size() != particles || e.particle_cue.size() != particles ||
      (!e.particle_vel.empty() && e.particle_vel.size() != particles))
    in.bad("per-particle arrays of different lengths");
  return c;
}

}  // namespace axg
