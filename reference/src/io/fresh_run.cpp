// A fresh run's folder: the steps `axonguide run` takes before and after the run itself,
// shared with the Python module's Result.write (docs/methods.md §7.1).
#include <exception>

#include "axonguide/checkpoint.hpp"
#include "axonguide/output.hpp"
#include "axonguide/run.hpp"
#include "axonguide/run_folder.hpp"

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
  running["replacing"] = replacing;
  running["files"] = json::object();
  // The running manifest first: from here on a kill leaves a folder whose manifest names
  // every file in it.
  write_manifest(dir, running);
  remove_run_files(dir, replacing);
  return running;
}

void abandon_fresh_run(const fs::path& dir, const Scene& scene) {
  std::error_code ec;
  remove_run_files(dir, planned_outputs(scene));
  fs::remove(dir / kManifestName, ec);
}

OutputInfo write_run_folder(const RunResult& result, const fs::path& dir, bool force, const std::string& backend,
                            int threads, const std::vector<std::string>& warnings, std::vector<std::string>* foreign) {
  const bool made_dir = !fs::exists(dir);
  std::exception_ptr failure;
  OutputInfo info;
  {
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
      failure = std::current_exception();
    }
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
