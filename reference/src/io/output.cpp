#include "axonguide/output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <vector>

#include <fmt/format.h>
#include <openssl/evp.h>

#include "axonguide/error.hpp"
#include "axonguide/fault.hpp"

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
}  // namespace

AtomicFile::AtomicFile(const fs::path& dir, const std::string& name, Sync sync)
    : final_(dir / name), temp_(dir / fmt::format(".{}.tmp-{}", name, ::getpid())), sync_(sync) {
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) throw RunError(fmt::format("cannot create {}: {}", temp_.string(), std::strerror(errno)));
  auto* ctx = EVP_MD_CTX_new();
  if (!ctx || EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr) != 1) throw RunError("SHA-256 unavailable");
  digest_ = ctx;
}

AtomicFile::~AtomicFile() {
  EVP_MD_CTX_free(static_cast<EVP_MD_CTX*>(digest_));
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicFile::Free::operator()(char* p) const { std::free(p); }

// The buffer starts small (most files are) and grows to one block.
void AtomicFile::grow(std::size_t at_least) {
  std::size_t capacity = std::max<std::size_t>(capacity_, std::size_t{1} << 16);
  while (capacity < at_least && capacity < kDirectBlock) capacity *= 4;
  capacity = std::min(capacity, kDirectBlock);
  void* p = nullptr;
  if (::posix_memalign(&p, 4096, capacity) != 0) throw std::bad_alloc();
  if (size_) std::memcpy(p, buffer_.get(), size_);
  buffer_.reset(static_cast<char*>(p));
  capacity_ = capacity;
}

void AtomicFile::write(std::string_view text) {
  EVP_DigestUpdate(static_cast<EVP_MD_CTX*>(digest_), text.data(), text.size());
  while (!text.empty()) {
    if (size_ == capacity_) {
      if (capacity_ < kDirectBlock)
        grow(size_ + text.size());
      else
        write_block();
    }
    const std::size_t n = std::min(text.size(), capacity_ - size_);
    std::memcpy(buffer_.get() + size_, text.data(), n);
    size_ += n;
    text.remove_prefix(n);
  }
}

bool AtomicFile::set_direct(bool on) {
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags < 0 || ::fcntl(fd_, F_SETFL, on ? flags | O_DIRECT : flags & ~O_DIRECT) != 0) return false;
  direct_ = on;
  return true;
}

// Direct I/O writes the block from this buffer to the disk: no page-cache pages to fill
// (on a VM whose host takes freed pages back, each fresh one costs a fault there too) and
// nothing left for the write-back. A file system that refuses it (tmpfs, some network
// file systems: EINVAL at fcntl or at the write) gets the page cache.
void AtomicFile::write_block() {
  if (!tried_direct_) tried_direct_ = true, set_direct(true);
  if (direct_) {
    ssize_t n;
    do n = ::write(fd_, buffer_.get(), size_);
    while (n < 0 && errno == EINTR);
    if (n == static_cast<ssize_t>(size_)) {
      wrote_direct_ = true;
      size_ = 0;
      return;
    }
    // A short or refused direct write: the rest through the page cache (the file offset
    // is where the written part ends).
    if (n < 0 && errno != EINVAL) throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(errno)));
    set_direct(false);
    const std::size_t done = n > 0 ? static_cast<std::size_t>(n) : 0;
    write_all(buffer_.get() + done, size_ - done);
  } else {
    write_all(buffer_.get(), size_);
  }
  size_ = 0;
}

void AtomicFile::write_all(const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd_, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(w < 0 ? errno : EIO)));
    data += w, n -= static_cast<std::size_t>(w);
  }
}

std::string AtomicFile::commit() {
  fault_point("output " + final_.filename().string());
  // The tail through the page cache (direct I/O takes whole blocks only).
  if (direct_ && !set_direct(false))
    throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(errno)));
  write_all(buffer_.get(), size_);
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
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  EVP_DigestFinal_ex(static_cast<EVP_MD_CTX*>(digest_), md, &len);
  return to_hex(md, len);
}

void sync_filesystem(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  const bool ok = fd >= 0 && ::syncfs(fd) == 0;
  const int err = errno;
  if (fd >= 0) ::close(fd);
  if (!ok) throw RunError(fmt::format("cannot sync {}: {}", dir.string(), std::strerror(err)));
}

Sha256::Sha256() : ctx_(EVP_MD_CTX_new()) {
  if (!ctx_ || EVP_DigestInit_ex(static_cast<EVP_MD_CTX*>(ctx_), EVP_sha256(), nullptr) != 1)
    throw RunError("SHA-256 unavailable");
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
