// AtomicFile on a file system that takes O_DIRECT at fcntl but then refuses the direct
// write (EINVAL), or takes only part of it: the rest of the file goes through the page
// cache, and the file holds every byte. No file system here refuses, so this test executable
// interposes write(2) (its own definition takes precedence over libc's for the whole
// process) and refuses, or shortens, writes made with O_DIRECT while `mode` says so.
#include <gtest/gtest.h>

#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <string>

#include "support.hpp"

namespace {

enum class Mode { kPass, kRefuse, kShort };
std::atomic<Mode> mode{Mode::kPass};
std::atomic<int> direct_writes{0};  // writes made with O_DIRECT set

}  // namespace

extern "C" ssize_t write(int fd, const void* data, size_t n) {
  using Write = ssize_t (*)(int, const void*, size_t);
  static const Write real = reinterpret_cast<Write>(::dlsym(RTLD_NEXT, "write"));
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0 && (flags & O_DIRECT)) {
    ++direct_writes;
    if (mode == Mode::kRefuse) {
      errno = EINVAL;
      return -1;
    }
    if (mode == Mode::kShort && n > 4096) return real(fd, data, n / 2 / 4096 * 4096);  // aligned, part of it
  }
  return real(fd, data, n);
}

namespace axg {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

constexpr std::size_t kBlock = AtomicFile::kDirectBlock;

// Writes three blocks and a tail under `m` and checks the file's bytes and hash; returns
// whether its blocks went direct.
bool write_under(Mode m) {
  TempDir dir;
  const std::string text = test::byte_pattern(3 * kBlock + 777, 1);
  mode = m;
  direct_writes = 0;
  AtomicFile f(dir.path(), "out.bin");
  for (std::size_t at = 0; at < text.size(); at += 100000) f.write(std::string_view(text).substr(at, 100000));
  const std::string hash = f.commit();
  mode = Mode::kPass;
  EXPECT_EQ(hash, sha256_hex(text));
  EXPECT_TRUE(test::read_file(dir.path() / "out.bin") == text) << "the file's bytes differ from those written";
  return f.wrote_direct();
}

TEST(AtomicFileFallback, ARefusedDirectWriteGoesThroughThePageCache) {
  EXPECT_FALSE(write_under(Mode::kRefuse));
  EXPECT_EQ(direct_writes.load(), 1);  // the first block tried once, then no more direct writes
}

TEST(AtomicFileFallback, AShortDirectWriteIsFinishedThroughThePageCache) {
  EXPECT_FALSE(write_under(Mode::kShort));
  EXPECT_EQ(direct_writes.load(), 1);  // half of the first block directly, the rest buffered
}

TEST(AtomicFileFallback, TheInterposerSeesDirectWrites) {
  // The control: without a refusal, all three whole blocks are direct writes.
  EXPECT_TRUE(write_under(Mode::kPass));
  EXPECT_EQ(direct_writes.load(), 3);
}

}  // namespace
}  // namespace axg
