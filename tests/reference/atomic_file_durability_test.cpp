// AtomicFile's durability, seen from the system calls it makes (fsync(2) interposed in this
// test's own process: its definition takes precedence over libc's): a kFile commit syncs
// the file, renames it, then syncs the directory, so that the new name itself survives a
// power loss; a kDeferred commit leaves both to sync_filesystem.
#include <gtest/gtest.h>

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <mutex>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

// Every fsync: whether its descriptor was a directory, and whether the file's final name
// existed at that moment.
struct Sync {
  bool directory;
  bool renamed;
};
std::mutex m;
std::vector<Sync> syncs;
std::string watched;  // the final path whose existence each fsync records

}  // namespace

extern "C" int fsync(int fd) {
  using Fsync = int (*)(int);
  static const Fsync real = reinterpret_cast<Fsync>(::dlsym(RTLD_NEXT, "fsync"));
  struct stat st {};
  const bool directory = ::fstat(fd, &st) == 0 && S_ISDIR(st.st_mode);
  {
    std::lock_guard<std::mutex> lock(m);
    syncs.push_back({directory, !watched.empty() && ::access(watched.c_str(), F_OK) == 0});
  }
  return real(fd);
}

namespace axg {
namespace {

std::vector<Sync> commit_under(AtomicFile::Sync mode, std::size_t bytes) {
  test::TempDir dir;
  {
    std::lock_guard<std::mutex> lock(m);
    syncs.clear();
    watched = (dir.path() / "f.bin").string();
  }
  AtomicFile f(dir.path(), "f.bin", mode);
  f.write(test::byte_pattern(bytes, 9));
  f.commit();
  std::lock_guard<std::mutex> lock(m);
  watched.clear();
  return syncs;
}

TEST(AtomicFileDurability, AFileCommitSyncsTheFileThenTheDirectoryAfterTheRename) {
  for (const std::size_t bytes : {std::size_t{0}, std::size_t{100}, AtomicFile::kDirectBlock + 5}) {
    const std::vector<Sync> s = commit_under(AtomicFile::Sync::kFile, bytes);
    ASSERT_EQ(s.size(), 2u) << bytes << " bytes";
    EXPECT_FALSE(s[0].directory);
    EXPECT_FALSE(s[0].renamed) << "the file is synced before its rename";
    EXPECT_TRUE(s[1].directory);
    EXPECT_TRUE(s[1].renamed) << "the directory is synced after the rename";
  }
}

TEST(AtomicFileDurability, ADeferredCommitLeavesTheSyncsToSyncFilesystem) {
  EXPECT_TRUE(commit_under(AtomicFile::Sync::kDeferred, 100).empty());
}

}  // namespace
}  // namespace axg
