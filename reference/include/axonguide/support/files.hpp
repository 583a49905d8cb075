#pragma once
// Output files (SPEC §4). Every file is written to a temporary name in the output
// directory and renamed when complete, so a crash never leaves a half file that looks
// whole; manifest.json is written last and holds the SHA-256 of every other file.
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace axg {

// Incremental SHA-256 (OpenSSL EVP).
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void update(std::string_view bytes);
  std::string hex();  // of everything updated so far; call once

 private:
  void* ctx_;  // EVP_MD_CTX
};

// A buffered file that becomes visible under its name only on commit(). A file of more than
// kDirectBlock bytes is written in whole blocks of that size with direct I/O (O_DIRECT,
// where the file system takes it): from the buffer to the disk, with no copy into the page
// cache, on a thread of the file's own while the caller fills the next block; its tail,
// and every smaller file, through the page cache.
class AtomicFile {
 public:
  // kFile: commit() syncs the file before the rename and its directory after it.
  // kDeferred: commit() starts the write-back and renames without waiting for it; the
  // writer of many files syncs them all at once with sync_filesystem before anything (the
  // manifest) names them.
  enum class Sync { kFile, kDeferred };
  AtomicFile(const std::filesystem::path& dir, const std::string& name, Sync sync = Sync::kFile);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Appends text. Throws RunError on a failure, including a block's failure on the writer
  // thread since the last call; after one failure every later write() and commit() throws it.
  void write(std::string_view text);
  // Flushes, syncs and renames into place; returns the hex SHA-256 of the bytes
  // written. Throws RunError on any I/O failure; a kFile commit whose directory sync fails
  // throws after the rename, with the file in place under its name.
  std::string commit();
  const std::filesystem::path& final_path() const { return final_; }

  static constexpr std::size_t kDirectBlock = std::size_t{4} << 20;  // bytes; a multiple of every block size
  // Whether the file's whole blocks went to the disk with direct I/O (for tests; after commit).
  bool wrote_direct() const { return wrote_direct_; }

 private:
  class BlockWriter;  // writes whole blocks on a thread of its own (output.cpp)
  struct Free {  // a block is its own mapping, given back whole; smaller buffers are malloc's
    std::size_t size;  // bytes (0 in the deleter of an empty pointer)
    void operator()(char* p) const;
  };
  static std::unique_ptr<char, Free> aligned_buffer(std::size_t size);
  void grow(std::size_t at_least);

  std::filesystem::path final_, temp_;
  int fd_ = -1;
  bool committed_ = false;
  bool wrote_direct_ = false;
  Sync sync_;
  Sha256 digest_;           // of the bytes buffered so far
  std::string failed_;      // the first write's failure, thrown again by every later call
  // The block being filled and the one the writer has, each aligned to 4096 bytes, as
  // direct I/O needs; the writer exists once the file has outgrown one block.
  std::unique_ptr<char, Free> buffer_, spare_;
  std::size_t size_ = 0, capacity_ = 0;
  std::unique_ptr<BlockWriter> blocks_;
};

// An AtomicFile's temporary name, ".NAME.tmp-PID": the NAME it stands for and the process
// that wrote it, or nothing when `filename` is not one.
struct TemporaryName {
  std::string name;
  long pid;
};
std::optional<TemporaryName> parse_temporary_name(const std::string& filename);

// Writes a whole file atomically (AtomicFile, write, commit); returns its SHA-256.
std::string write_file_atomically(const std::filesystem::path& dir, const std::string& name, std::string_view text);

// Creates dir (and its parents) for output files; RunError naming it when it cannot.
void create_output_dir(const std::filesystem::path& dir);

// A fresh directory of this process's own (mkdtemp: a name no one can prepare in advance,
// mode 0700) in `parent` (the system's temporary directory by default), removed with all it
// holds when this goes out of scope, however that happens. RunError when it cannot be made.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix, const std::filesystem::path& parent = {});
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Syncs the file system that holds dir (syncfs): the deferred AtomicFiles written there
// are on disk when it returns. Throws RunError when it fails.
void sync_filesystem(const std::filesystem::path& dir);

// Hex SHA-256 of a file's bytes (OpenSSL EVP).
std::string sha256_file(const std::filesystem::path& path);
std::string sha256_hex(std::string_view bytes);

// Creates the directory if needed; InputError when the path exists and is not a
// directory or cannot be created.
void prepare_output_dir(const std::filesystem::path& dir);

}  // namespace axg
