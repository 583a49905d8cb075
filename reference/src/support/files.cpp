#include "axonguide/support/files.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <openssl/evp.h>

#include "axonguide/support/error.hpp"
#include "axonguide/support/fault.hpp"

namespace axg {

namespace fs = std::filesystem;

namespace {
std::string to_hex(const unsigned char* md, unsigned int len) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * len);
  for (unsigned int i = 0; i < len; ++i) {
    hex += digits[md[i] >> 4];
    hex += digits[md[i] & 15];
  }
  return hex;
}

bool set_direct(int fd, bool on) {
  const int flags = ::fcntl(fd, F_GETFL);
  return flags >= 0 && ::fcntl(fd, F_SETFL, on ? flags | O_DIRECT : flags & ~O_DIRECT) == 0;
}

// write(2) until all n bytes are written; RunError naming the file on failure.
void write_all(int fd, const char* data, std::size_t n, const fs::path& name) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw RunError(fmt::format("cannot write {}: {}", name.string(), std::strerror(w < 0 ? errno : EIO)));
    data += w, n -= static_cast<std::size_t>(w);
  }
}

// sync(fd) on a descriptor of the directory: fsync (its entries, a rename into it) or
// syncfs (its whole file system). RunError naming the directory when it fails.
void sync_on_directory(const fs::path& dir, int (*sync)(int)) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  const bool ok = fd >= 0 && sync(fd) == 0;
  const int err = errno;
  if (fd >= 0) ::close(fd);
  if (!ok) throw RunError(fmt::format("cannot sync {}: {}", dir.string(), std::strerror(err)));
}

}  // namespace

// Whole blocks go to the file on this thread, one at a time, in order, while the caller
// fills the next. Direct I/O writes a block from the caller's buffer to the disk: no
// page-cache pages to fill (on a VM whose host takes freed pages back, each fresh one costs
// a fault there too), and nothing left for the write-back. A file system that refuses it
// (fcntl fails, or the write fails with EINVAL or EOPNOTSUPP) gets the page cache.
class AtomicFile::BlockWriter {
 public:
  BlockWriter(int fd, fs::path name) : fd_(fd), name_(std::move(name)), thread_([this] { run(); }) {}
  ~BlockWriter() {
    {
      std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();  // after the block in flight
  }

  // Waits until the block before is written, then takes this one (which must stay as it is
  // until the next submit or finish returns). RunError: a block before failed.
  void submit(const char* block, std::size_t size) {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [&] { return job_ == nullptr; });
    if (!error_.empty()) throw RunError(error_);
    job_ = block, job_size_ = size;
    cv_.notify_all();
  }
  // Waits until every block is written; RunError if one failed. Returns whether O_DIRECT
  // is still set on the file.
  bool finish() {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [&] { return job_ == nullptr; });
    if (!error_.empty()) throw RunError(error_);
    return direct_;
  }
  bool wrote_direct() const { return wrote_direct_; }  // after finish()
  // Whether a block has failed (finish() then throws why): write() asks before each piece,
  // so a failure is a RunError at the next write, not only at the next block handed over.
  bool failed() const { return failed_.load(std::memory_order_acquire); }

 private:
  void run() {
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
      cv_.wait(lock, [&] { return job_ != nullptr || stop_; });
      if (job_ == nullptr) return;
      lock.unlock();
      std::string error;
      try {
        write_block(job_, job_size_);
      } catch (const std::exception& e) {
        error = e.what();
      }
      lock.lock();
      if (error_.empty() && !error.empty()) {
        error_ = std::move(error);
        failed_.store(true, std::memory_order_release);
      }
      job_ = nullptr;
      cv_.notify_all();
    }
  }

  void write_block(const char* block, std::size_t size) {
    if (!tried_direct_) tried_direct_ = true, direct_ = set_direct(fd_, true);
    if (direct_) {
      ssize_t n;
      do n = ::write(fd_, block, size);
      while (n < 0 && errno == EINTR);
      if (n == static_cast<ssize_t>(size)) {
        wrote_direct_ = true;
        return;
      }
      // A short or refused direct write: the rest through the page cache (the file offset
      // is where the written part ends).
      const bool refused = n < 0 && (errno == EINVAL || errno == EOPNOTSUPP || errno == ENOTSUP);
      if (n < 0 && !refused) throw RunError(fmt::format("cannot write {}: {}", name_.string(), std::strerror(errno)));
      direct_ = !set_direct(fd_, false);
      if (direct_) throw RunError(fmt::format("cannot write {}: {}", name_.string(), std::strerror(errno)));
      const std::size_t done = n > 0 ? static_cast<std::size_t>(n) : 0;
      block += done, size -= done;
    }
    write_all(fd_, block, size, name_);
  }

  int fd_;
  fs::path name_;
  bool tried_direct_ = false, direct_ = false, wrote_direct_ = false;  // the writer thread's (read after finish)
  std::mutex m_;
  std::condition_variable cv_;
  const char* job_ = nullptr;  // the block in flight
  std::size_t job_size_ = 0;
  bool stop_ = false;
  std::string error_;  // the first block's failure
  std::atomic<bool> failed_{false};  // error_ is set
  std::thread thread_;  // last: started once the rest is constructed
};

// The open last: a constructor that throws runs no destructor of its own (the members'
// run), so nothing may be open or on the disk before it.
AtomicFile::AtomicFile(const fs::path& dir, const std::string& name, Sync sync)
    : final_(dir / name), temp_(dir / fmt::format(".{}.tmp-{}", name, ::getpid())), sync_(sync) {
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) throw RunError(fmt::format("cannot create {}: {}", temp_.string(), std::strerror(errno)));
}

AtomicFile::~AtomicFile() {
  blocks_.reset();  // the block in flight is written first
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

// A block-sized buffer is mapped and unmapped on its own: from the heap, the freed blocks
// would stay with the process and could raise the peak of what is allocated after them
// (the SONATA writer's arrays, after bfs.csv: 9 MB at 10^7 neurons).
void AtomicFile::Free::operator()(char* p) const {
  if (size >= kDirectBlock)
    ::munmap(p, size);
  else
    std::free(p);
}

std::unique_ptr<char, AtomicFile::Free> AtomicFile::aligned_buffer(std::size_t size) {
  void* p = nullptr;
  if (size >= kDirectBlock) {
    p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
  } else if (::posix_memalign(&p, 4096, size) != 0) {
    throw std::bad_alloc();
  }
  return std::unique_ptr<char, Free>(static_cast<char*>(p), Free{size});
}

// The buffer starts small (most files are) and grows to one block.
void AtomicFile::grow(std::size_t at_least) {
  std::size_t capacity = std::max<std::size_t>(capacity_, std::size_t{1} << 16);
  while (capacity < at_least && capacity < kDirectBlock) capacity *= 4;
  capacity = std::min(capacity, kDirectBlock);
  auto p = aligned_buffer(capacity);
  if (size_) std::memcpy(p.get(), buffer_.get(), size_);
  buffer_ = std::move(p);
  capacity_ = capacity;
}

// Each piece is hashed as it is buffered, so the hash covers exactly the bytes the file
// gets. The first failure (a block the writer thread could not write, a buffer or a thread
// that could not be had) is kept: every later write() and commit() throws it, so a caller
// that goes on after one (an std::ostream swallows its streambuf's exceptions) cannot
// commit a file that lacks bytes.
void AtomicFile::write(std::string_view text) {
  if (!failed_.empty()) throw RunError(failed_);
  try {
    if (blocks_ && blocks_->failed()) blocks_->finish();  // throws the block's failure
    while (!text.empty()) {
      if (size_ == capacity_) {
        if (capacity_ < kDirectBlock) {
          grow(size_ + text.size());
        } else {
          if (!blocks_) spare_ = aligned_buffer(kDirectBlock), blocks_ = std::make_unique<BlockWriter>(fd_, temp_);
          blocks_->submit(buffer_.get(), size_);  // the spare is free once this returns
          std::swap(buffer_, spare_);
          size_ = 0;
        }
      }
      const std::size_t n = std::min(text.size(), capacity_ - size_);
      std::memcpy(buffer_.get() + size_, text.data(), n);
      digest_.update(text.substr(0, n));
      size_ += n;
      text.remove_prefix(n);
    }
  } catch (const RunError& e) {
    failed_ = e.what();
    throw;
  } catch (const std::exception& e) {
    failed_ = fmt::format("cannot write {}: {}", temp_.string(), e.what());
    throw RunError(failed_);
  }
}

std::string AtomicFile::commit() {
  if (!failed_.empty()) throw RunError(failed_);
  fault_point("output " + final_.filename().string());
  // The tail through the page cache (direct I/O takes whole blocks only).
  if (blocks_) {
    const bool direct = blocks_->finish();
    wrote_direct_ = blocks_->wrote_direct();
    blocks_.reset();
    if (direct && !set_direct(fd_, false))
      throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(errno)));
  }
  write_all(fd_, buffer_.get(), size_, temp_);
  size_ = 0;
  // Deferred: the write-back starts now (sync_file_range does not wait for it), and
  // sync_filesystem waits for it later.
  const bool ok = sync_ == Sync::kDeferred ? ::sync_file_range(fd_, 0, 0, SYNC_FILE_RANGE_WRITE) == 0
                                           : ::fsync(fd_) == 0;
  const int err = errno;
  const bool closed = ::close(fd_) == 0;
  fd_ = -1;
  if (!ok || !closed)
    throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(ok ? errno : err)));
  std::error_code ec;
  fs::rename(temp_, final_, ec);
  if (ec) throw RunError(fmt::format("cannot rename {} to {}: {}", temp_.string(), final_.string(), ec.message()));
  committed_ = true;
  // kFile: the rename itself on disk too (the directory's entry), so that a file that
  // commit() returned for (a manifest, a checkpoint) is found under its name after a power
  // loss. kDeferred files are covered by sync_filesystem, which syncs the directories too.
  if (sync_ == Sync::kFile) sync_on_directory(final_.parent_path(), ::fsync);
  return digest_.hex();
}

void create_output_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", dir.string(), ec.message()));
}

void sync_filesystem(const fs::path& dir) { sync_on_directory(dir, ::syncfs); }

Sha256::Sha256() : ctx_(EVP_MD_CTX_new()) {
  if (!ctx_ || EVP_DigestInit_ex(static_cast<EVP_MD_CTX*>(ctx_), EVP_sha256(), nullptr) != 1) {
    EVP_MD_CTX_free(static_cast<EVP_MD_CTX*>(ctx_));  // no destructor after a throw
    throw RunError("SHA-256 unavailable");
  }
}

Sha256::~Sha256() { EVP_MD_CTX_free(static_cast<EVP_MD_CTX*>(ctx_)); }

void Sha256::update(std::string_view bytes) { EVP_DigestUpdate(static_cast<EVP_MD_CTX*>(ctx_), bytes.data(), bytes.size()); }

std::string Sha256::hex() {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  EVP_DigestFinal_ex(static_cast<EVP_MD_CTX*>(ctx_), md, &len);
  return to_hex(md, len);
}

std::string write_file_atomically(const std::filesystem::path& dir, const std::string& name, std::string_view text) {
  AtomicFile f(dir, name);
  f.write(text);
  return f.commit();
}

std::string sha256_hex(std::string_view bytes) {
  Sha256 d;
  d.update(bytes);
  return d.hex();
}

std::string sha256_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RunError(fmt::format("cannot read {} for hashing", path.string()));
  Sha256 d;
  std::vector<char> buf(1 << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    d.update(std::string_view(buf.data(), static_cast<std::size_t>(in.gcount())));
  }
  return d.hex();
}

std::optional<TemporaryName> parse_temporary_name(const std::string& filename) {
  if (filename.size() < 2 || filename[0] != '.') return std::nullopt;
  const auto at = filename.rfind(".tmp-");
  if (at == std::string::npos || at < 2) return std::nullopt;
  const std::string pid = filename.substr(at + 5);
  if (pid.empty() || pid.size() > 9 || pid.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  return TemporaryName{filename.substr(1, at - 1), std::stol(pid)};
}

ScratchDir::ScratchDir(const std::string& prefix, const fs::path& parent) {
  const fs::path base = parent.empty() ? fs::temp_directory_path() : parent;
  std::string name = (base / (prefix + "-XXXXXX")).string();
  if (!::mkdtemp(name.data()))
    throw RunError(fmt::format("cannot make a scratch directory in {}: {}", base.string(), std::strerror(errno)));
  path_ = name;
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

void prepare_output_dir(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(fmt::format("--out {}: exists and is not a directory", dir.string()));
  fs::create_directories(dir, ec);
  if (ec) throw InputError(fmt::format("--out {}: cannot create directory: {}", dir.string(), ec.message()));
  if (::access(dir.c_str(), W_OK) != 0)
    throw InputError(fmt::format("--out {}: directory is not writable", dir.string()));
}

}  // namespace axg
