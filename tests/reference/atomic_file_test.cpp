// AtomicFile: whatever the sizes of the writes, the file holds their bytes in order and
// commit() returns their SHA-256; a file of more than one block goes to the disk with
// direct I/O where the file system takes it, its tail through the page cache; an
// uncommitted file leaves nothing behind.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "support.hpp"

namespace axg {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

constexpr std::size_t kBlock = AtomicFile::kDirectBlock;

// Whether the file system of dir takes an aligned direct write.
bool direct_io_works(const fs::path& dir) {
  const fs::path probe = dir / "probe";
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_DIRECT, 0644);
  if (fd < 0) return false;
  void* p = nullptr;
  bool ok = ::posix_memalign(&p, 4096, 4096) == 0;
  if (ok) {
    std::memset(p, 0, 4096);
    ok = ::write(fd, p, 4096) == 4096;
  }
  std::free(p);
  ::close(fd);
  fs::remove(probe);
  return ok;
}

RC_GTEST_PROP(AtomicFileWrites, HoldsTheWrittenBytesAndTheirHash, ()) {
  // Sizes around the block: empty writes, small ones, ones that end a block exactly, and
  // ones larger than a block.
  const auto sizes = *rc::gen::container<std::vector<std::size_t>>(
      *rc::gen::inRange<std::size_t>(0, 6),
      rc::gen::oneOf(rc::gen::inRange<std::size_t>(0, 5000), rc::gen::just(kBlock), rc::gen::just(kBlock - 1),
                     rc::gen::inRange<std::size_t>(kBlock - 4096, kBlock + 4097),
                     rc::gen::inRange<std::size_t>(0, 2 * kBlock + 3)));
  TempDir dir;
  std::string all;
  std::string hash;
  {
    AtomicFile f(dir.path(), "out.bin", *rc::gen::element(AtomicFile::Sync::kFile, AtomicFile::Sync::kDeferred));
    std::uint32_t salt = 0;
    for (std::size_t n : sizes) {
      const std::string chunk = test::byte_pattern(n, ++salt);
      f.write(chunk);
      all += chunk;
    }
    hash = f.commit();
  }
  RC_ASSERT(test::read_file(dir.path() / "out.bin") == all);
  RC_ASSERT(hash == sha256_hex(all));
  std::vector<fs::path> left;
  for (const auto& e : fs::directory_iterator(dir.path())) left.push_back(e.path().filename());
  RC_ASSERT(left == std::vector<fs::path>{"out.bin"});
}

TEST(AtomicFileWrites, LargeFileGoesDirectWhereTheFileSystemTakesIt) {
  TempDir dir;
  if (!direct_io_works(dir.path())) GTEST_SKIP() << dir.path() << ": the file system refuses direct I/O";
  const std::string big = test::byte_pattern(2 * kBlock + 12345, 7), small = test::byte_pattern(kBlock, 8);
  AtomicFile f(dir.path(), "big.bin"), g(dir.path(), "small.bin");
  f.write(big);
  g.write(small);  // one block exactly: nothing is written before commit, all of it buffered
  EXPECT_EQ(f.commit(), sha256_hex(big));
  EXPECT_EQ(g.commit(), sha256_hex(small));
  EXPECT_TRUE(f.wrote_direct());
  EXPECT_FALSE(g.wrote_direct());
  EXPECT_EQ(test::read_file(dir.path() / "big.bin"), big);
  EXPECT_EQ(test::read_file(dir.path() / "small.bin"), small);
  EXPECT_EQ(fs::file_size(dir.path() / "big.bin"), big.size());
}

// A block that cannot be written (here: the file-size limit, EFBIG, on the writer's thread)
// is a RunError on the caller's thread, already at the next block handed over (not only at
// commit, whose own tail write would fail too), and the temporary file is gone.
TEST(AtomicFileWrites, AFailedBlockIsARunErrorAndLeavesNothing) {
  TempDir dir;
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit = before;
  limit.rlim_cur = kBlock + kBlock / 2;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string error;
  bool committing = false;
  try {
    AtomicFile f(dir.path(), "big.bin");
    for (int k = 0; k < 4; ++k) f.write(test::byte_pattern(kBlock, static_cast<std::uint32_t>(k)));
    committing = true;
    f.commit();
  } catch (const RunError& e) {
    error = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_FALSE(committing) << "the failed block was reported only at commit";
  EXPECT_NE(error.find("cannot write"), std::string::npos) << error;
  EXPECT_NE(error.find("big.bin"), std::string::npos) << error;
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(AtomicFileWrites, UncommittedFileLeavesNothing) {
  TempDir dir;
  {
    AtomicFile f(dir.path(), "gone.bin");
    f.write(test::byte_pattern(kBlock + 10, 3));  // one block already on the disk
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

}  // namespace
}  // namespace axg
