#pragma once
// A run owns its folder (SPEC §4). manifest.json says what the folder is:
//   "status": "running"      a run is writing it (or was killed while it did);
//   "status": "interrupted"  a run stopped on SIGINT/SIGTERM after writing a checkpoint;
//   "status": "complete"     every output is written, and "files" lists each one with its
//                            SHA-256 (the manifest is written last).
// A folder is a whole run exactly when its manifest is complete and every file it lists
// has the listed hash. Readers (view, plot, assay, golden) refuse anything else, and read
// only the files the manifest lists.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/scene/scene.hpp"

namespace axg {

inline constexpr const char* kManifestName = "manifest.json";
inline constexpr const char* kLockName = ".axonguide.lock";
// Where `--force` keeps the complete run it replaces until the new run is whole (then it is
// removed), or fails before it has a checkpoint (then it is put back): DIR/.replaced/, the
// old run's files under their own names and its manifest.
inline constexpr const char* kReplacedName = ".replaced";

// True for the names a run writes (relative to its folder): its CSV, GraphML and VTK
// files, the manifest and the checkpoint.
bool is_run_output(const std::string& relative_name);

struct FolderCheck {
  bool whole = false;
  std::string status;                 // "complete", "running", "interrupted", or empty
  std::vector<std::string> problems;  // why it is not whole
  std::vector<std::string> notes;     // harmless findings (e.g. an old checkpoint)
  nlohmann::json manifest;            // null when missing or unreadable
};

// Checks DIR against DIR/manifest.json: status, presence and SHA-256 of every listed file.
FolderCheck verify_run_folder(const std::filesystem::path& dir);

// The manifest of a whole run; throws InputError "COMMAND: DIR is not a whole run: ..."
// (exit 2) otherwise.
nlohmann::json require_whole_run(const std::filesystem::path& dir, const std::string& command);

// An exclusive lock on DIR/.axonguide.lock (flock: released by the kernel when the
// process dies, so kill -9 leaves no stale lock). Throws RunError when another process
// holds it. The file is removed when the lock is released.
class FolderLock {
 public:
  explicit FolderLock(const std::filesystem::path& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

// What a new run in DIR must replace. An empty folder, or one holding only files a run
// does not write, is taken as it is. A folder holding a run (any status) is refused
// unless `force`; with force, `replacing` is exactly the files its manifest lists (with
// the manifest and the checkpoint). Run outputs without a manifest are refused even with
// force: nothing says whose they are. Nothing is moved or removed here: the new run first
// writes its running manifest, which lists `replacing`, and then moves them into
// DIR/.replaced/ (a complete run's) or removes them (an unfinished run's), so that a kill at
// any point leaves a manifest naming every file.
struct FolderClaim {
  std::vector<std::string> replacing;
  std::vector<std::string> foreign;  // files left that no run wrote (notes, view.html, plots)
  // The complete run kept in DIR/.replaced/ while the new one runs: kMake, the old run is
  // complete and goes there; kKeep, the old run is an unfinished replacement of a complete
  // run that is there already (its files named in `keeping` were not yet moved); kNone.
  enum class Replaced { kNone, kMake, kKeep } replaced = Replaced::kNone;
  std::vector<std::string> keeping;
};
FolderClaim claim_run_folder(const std::filesystem::path& dir, bool force);

// Refuses (InputError, exit 2) a claim whose foreign files the new run of `scene` would
// write over, or remove if it failed: a file under a name the run plans ("paths.csv"), or in
// a subfolder whose files it writes ("vtk/*.vtp"), that the old manifest does not list.
void refuse_foreign_in_the_way(const std::filesystem::path& dir, const FolderClaim& claim, const Scene& scene);

// Removes these files of DIR (names relative to it; "vtk/*.vtp" for the VTK frames),
// the temporary files of killed runs, and vtk/ when it is left empty.
void remove_run_files(const std::filesystem::path& dir, const std::vector<std::string>& names);

// Removes the temporary files (".NAME.tmp-PID") of runs that were killed in DIR.
void remove_stale_temporaries(const std::filesystem::path& dir);

// Whether an unfinished run's manifest says that DIR/.replaced/ keeps the run it replaces.
bool keeps_replaced_run(const nlohmann::json& manifest);

// Makes DIR/.replaced/ (removing one a killed run left) and copies DIR's manifest into it,
// byte for byte and synced: the first step of keeping a complete run that --force replaces.
void make_replaced_run(const std::filesystem::path& dir);

// Moves these files of DIR (names as for remove_run_files) into DIR/.replaced/ under the
// same names. A name that .replaced/ holds already was moved before a kill, and the file in
// DIR is the new run's: it is removed, never moved over the kept one.
void keep_replaced_files(const std::filesystem::path& dir, const std::vector<std::string>& names);

// Puts the run kept in DIR/.replaced/ back: the files its manifest lists, then its manifest
// over the running one. False when .replaced/ holds no manifest (nothing to put back).
bool restore_replaced_run(const std::filesystem::path& dir);

// Removes DIR/.replaced/, once the run that replaced it is whole (a failure is a warning:
// the new run is whole all the same; a --resume or --force into DIR removes it).
void discard_replaced_run(const std::filesystem::path& dir);

// A fresh run's start, after claim_run_folder, by the holder of DIR's lock: an old
// checkpoint is removed first (it must never be taken for this run's); a complete run's
// manifest is copied into DIR/.replaced/; then the running manifest (status "running",
// "planned": planned_outputs, "replacing": the claim's files, "replaced_run": ".replaced"
// when one is kept) is written; then the files it replaces are moved into .replaced/ (or
// removed, an unfinished run's), and the manifest is written again with "replacing" empty.
// Returns that manifest.
nlohmann::json start_fresh_run(const std::filesystem::path& dir, const FolderClaim& claim, const Scene& scene,
                               const std::string& backend, int threads, const std::vector<std::string>& warnings);

// Takes back a fresh run that failed before its first checkpoint: its partial outputs and
// its running manifest, and puts back the run it replaced (restore_replaced_run). The
// caller removes DIR when it made it and it is left empty.
// Never throws: a failure here is a warning beside the failure being reported.
void abandon_fresh_run(const std::filesystem::path& dir, const Scene& scene) noexcept;

struct RunResult;
struct OutputInfo;
// Writes a finished run into DIR as `axonguide run --out DIR [--force]` does: creates DIR,
// takes its lock, claims it (refused when it holds a run, unless force), start_fresh_run,
// write_outputs; a failure takes the run back (abandon_fresh_run, and DIR when this made
// it). `foreign` receives the files left in DIR that are not the run's. The bytes of
// every file but timings.csv and the manifest's run facts are those of `axonguide run`.
OutputInfo write_run_folder(const RunResult& result, const std::filesystem::path& dir, bool force,
                            const std::string& backend, int threads, const std::vector<std::string>& warnings,
                            std::vector<std::string>* foreign = nullptr);

// The manifest's fields that describe the run (everything but status, files and
// timings): version, build, scene, seed, units, backend, threads, created, warnings.
nlohmann::json manifest_header(const Scene& scene, const std::string& backend, int threads,
                               const std::vector<std::string>& warnings);

// Writes DIR/manifest.json atomically.
void write_manifest(const std::filesystem::path& dir, const nlohmann::json& manifest);

// Reads DIR/manifest.json; throws InputError when it is missing or not JSON.
nlohmann::json read_manifest(const std::filesystem::path& dir);

}  // namespace axg
