// A fresh run's folder: the steps `axonguide run` takes before and after the run itself,
// shared with the Python module's Result.write (docs/guide.md §1.1).
#include <cstdio>
#include <exception>

#include "axonguide/engine/checkpoint.hpp"
#include "axonguide/support/error.hpp"
#include "axonguide/support/files.hpp"
#include "axonguide/engine/run.hpp"
#include "axonguide/io/run_folder.hpp"

namespace axg {

namespace fs = std::filesystem;
using nlohmann::json;

json start_fresh_run(const fs::path& dir, const FolderClaim& claim, const Scene& scene, const std::string& backend,
                     int threads, const std::vector<std::string>& warnings) {
  json running = manifest_header(scene, backend, threads, warnings);
  running["status"] = "running";
  running["planned"] = planned_outputs(scene);
  std::vector<std::string> replacing;
  for (const auto& name : claim.replacing)
    if (name == kCheckpointName) fs::remove(dir / name);
    else replacing.push_back(name);
  using Replaced = FolderClaim::Replaced;
  if (claim.replaced == Replaced::kMake)
    make_replaced_run(dir);  // the complete run's manifest, before the running one replaces it
  else if (claim.replaced == Replaced::kNone)
    discard_replaced_run(dir);  // one left by a run killed after it was whole
  if (claim.replaced != Replaced::kNone) running["replaced_run"] = kReplacedName;
  std::vector<std::string> listed = replacing;
  listed.insert(listed.end(), claim.keeping.begin(), claim.keeping.end());
  running["replacing"] = listed;
  running["files"] = json::object();
  // The running manifest first: from here on a kill leaves a folder whose manifest names
  // every file in it.
  write_manifest(dir, running);
  if (claim.replaced == Replaced::kMake) {
    keep_replaced_files(dir, replacing);
  } else {
    keep_replaced_files(dir, claim.keeping);  // those an unfinished replacement had not yet moved
    remove_run_files(dir, replacing);
  }
  if (!listed.empty()) {
    sync_filesystem(dir);  // the moves, before the manifest stops naming the files
    running["replacing"] = json::array();
    write_manifest(dir, running);
  }
  return running;
}

void abandon_fresh_run(const fs::path& dir, const Scene& scene) noexcept {
  // Called while a failure is being reported: that failure is the one to report, and this
  // one's is said beside it.
  try {
    remove_run_files(dir, planned_outputs(scene));
    if (restore_replaced_run(dir)) return;
    std::error_code ec;
    fs::remove(dir / kManifestName, ec);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "axonguide: warning: %s could not be taken back%s: %s\n", dir.c_str(),
                 fs::exists(dir / kReplacedName) ? " (the run it replaces is kept in .replaced/)" : "", e.what());
  }
}

OutputInfo write_run_folder(const RunResult& result, const fs::path& dir, bool force, const std::string& backend,
                            int threads, const std::vector<std::string>& warnings, std::vector<std::string>* foreign) {
  const bool made_dir = !fs::exists(dir);
  std::exception_ptr failure;
  OutputInfo info;
  try {
    prepare_output_dir(dir);
    FolderLock lock(dir);
    const FolderClaim claim = claim_run_folder(dir, force);
    refuse_foreign_in_the_way(dir, claim, result.scene);
    if (foreign) *foreign = claim.foreign;
    start_fresh_run(dir, claim, result.scene, backend, threads, warnings);
    try {
      info = write_outputs(result, dir, backend, threads, warnings);
    } catch (...) {
      abandon_fresh_run(dir, result.scene);
      throw;
    }
    discard_replaced_run(dir);  // the new run is whole
  } catch (...) {
    failure = std::current_exception();  // the lock (its file) is gone from here on
  }
  if (failure) {
    // After the lock (its file) is gone, as `axonguide run` does.
    std::error_code ec;
    if (made_dir && fs::is_empty(dir, ec)) fs::remove(dir, ec);
    std::rethrow_exception(failure);
  }
  return info;
}

}  // namespace axg
