#include "axonguide/output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
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
  file_ = std::fopen(temp_.c_str(), "wb");
  if (!file_)
    throw RunError(fmt::format("cannot create {}: {}", temp_.string(), std::strerror(errno)));
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  auto* ctx = EVP_MD_CTX_new();
  if (!ctx || EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr) != 1) throw RunError("SHA-256 unavailable");
  digest_ = ctx;
}

AtomicFile::~AtomicFile() {
  EVP_MD_CTX_free(static_cast<EVP_MD_CTX*>(digest_));
  if (file_) std::fclose(file_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicFile::write(std::string_view text) {
  EVP_DigestUpdate(static_cast<EVP_MD_CTX*>(digest_), text.data(), text.size());
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size())
    throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(errno)));
}

std::string AtomicFile::commit() {
  fault_point("output " + final_.filename().string());
  // Deferred: the write-back starts now (sync_file_range does not wait for it), and
  // sync_filesystem waits for it later.
  const bool ok = std::fflush(file_) == 0 &&
                  (sync_ == Sync::kDeferred ? ::sync_file_range(::fileno(file_), 0, 0, SYNC_FILE_RANGE_WRITE) == 0
                                            : ::fsync(::fileno(file_)) == 0);
  const int err = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed)
    throw RunError(fmt::format("cannot write {}: {}", temp_.string(), std::strerror(err)));
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
