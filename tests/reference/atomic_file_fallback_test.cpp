// AtomicFile on a file system that refuses direct I/O in one of the ways one can: at fcntl
// (F_SETFL O_DIRECT), or at the write (EINVAL or EOPNOTSUPP), or by taking only part of a
// direct write, on the first block or a later one. The rest of the file goes through the
// page cache, and the file holds every byte. No file system here refuses, so this test
// executable interposes write(2) and fcntl(2) (its own definitions take precedence over
// libc's for the whole process) and refuses, or shortens, while `mode` says so.
#include <gtest/gtest.h>

#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdarg>
#include <string>

#include "support.hpp"

namespace {

enum class Mode { kPass, kRefuse, kNotSupported, kShort, kShortSecond, kNoFcntl };
std::atomic<Mode> mode{Mode::kPass};
std::atomic<int> direct_writes{0};  // writes made with O_DIRECT set

using Fcntl = int (*)(int, int, ...);
Fcntl real_fcntl() {
  static const Fcntl real = reinterpret_cast<Fcntl>(::dlsym(RTLD_NEXT, "fcntl"));
  return real;
}

}  // namespace

extern "C" int fcntl(int fd, int cmd, ...) {
  if (cmd == F_GETFL || cmd == F_GETFD) return real_fcntl()(fd, cmd);
  va_list ap;
  va_start(ap, cmd);
  const long arg = va_arg(ap, long);  // an int or a pointer: passed on as it came
  va_end(ap);
  if (cmd == F_SETFL && (arg & O_DIRECT) && mode == Mode::kNoFcntl) {
    errno = EINVAL;
    return -1;
  }
  return real_fcntl()(fd, cmd, arg);
}

extern "C" ssize_t write(int fd, const void* data, size_t n) {
  using Write = ssize_t (*)(int, const void*, size_t);
  static const Write real = reinterpret_cast<Write>(::dlsym(RTLD_NEXT, "write"));
  const int flags = real_fcntl()(fd, F_GETFL);
  if (flags >= 0 && (flags & O_DIRECT)) {
    const int k = ++direct_writes;
    const Mode m = mode;
    if (m == Mode::kRefuse || m == Mode::kNotSupported) {
      errno = m == Mode::kRefuse ? EINVAL : EOPNOTSUPP;
      return -1;
    }
    const bool shorten = m == Mode::kShort || (m == Mode::kShortSecond && k == 2);
    if (shorten && n > 4096) return real(fd, data, n / 2 / 4096 * 4096);  // aligned, part of it
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
  struct Under {  // the mode for this file only, whatever happens
    explicit Under(Mode m) { mode = m, direct_writes = 0; }
    ~Under() { mode = Mode::kPass; }
  } under(m);
  AtomicFile f(dir.path(), "out.bin");
  for (std::size_t at = 0; at < text.size(); at += 100000) f.write(std::string_view(text).substr(at, 100000));
  const std::string hash = f.commit();
  EXPECT_EQ(hash, sha256_hex(text));
  EXPECT_TRUE(test::read_file(dir.path() / "out.bin") == text) << "the file's bytes differ from those written";
  return f.wrote_direct();
}

// The interposer only sees a refusal where the file system itself takes direct I/O.
class AtomicFileFallback : public ::testing::Test {
 protected:
  void SetUp() override {
    mode = Mode::kPass, direct_writes = 0;
    TempDir probe;
    if (!test::direct_io_works(probe.path()))
      GTEST_SKIP() << probe.path() << ": the file system refuses direct I/O of its own";
  }
};

TEST_F(AtomicFileFallback, ARefusedDirectWriteGoesThroughThePageCache) {
  EXPECT_FALSE(write_under(Mode::kRefuse));
  EXPECT_EQ(direct_writes.load(), 1);  // the first block tried once, then no more direct writes
}

TEST_F(AtomicFileFallback, ADirectWriteRefusedAsUnsupportedGoesThroughThePageCache) {
  EXPECT_FALSE(write_under(Mode::kNotSupported));
  EXPECT_EQ(direct_writes.load(), 1);
}

TEST_F(AtomicFileFallback, ARefusedFcntlKeepsThePageCache) {
  EXPECT_FALSE(write_under(Mode::kNoFcntl));
  EXPECT_EQ(direct_writes.load(), 0);  // O_DIRECT was never set
}

TEST_F(AtomicFileFallback, AShortDirectWriteIsFinishedThroughThePageCache) {
  EXPECT_FALSE(write_under(Mode::kShort));
  EXPECT_EQ(direct_writes.load(), 1);  // half of the first block directly, the rest buffered
}

TEST_F(AtomicFileFallback, AShortDirectWriteAfterWholeOnesIsFinishedThroughThePageCache) {
  // The first block whole and direct, half of the second direct, the rest buffered from where
  // the direct part ended.
  EXPECT_TRUE(write_under(Mode::kShortSecond));
  EXPECT_EQ(direct_writes.load(), 2);
}

TEST_F(AtomicFileFallback, TheInterposerSeesDirectWrites) {
  // The control: without a refusal, all three whole blocks are direct writes.
  EXPECT_TRUE(write_under(Mode::kPass));
  EXPECT_EQ(direct_writes.load(), 3);
}

}  // namespace
}  // namespace axg
