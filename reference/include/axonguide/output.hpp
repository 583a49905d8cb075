#pragma once
// Output files (SPEC §4). Every file is written to a temporary name in the output
// directory and renamed when complete, so a crash never leaves a half file that looks
// whole; manifest.json is written last and holds the SHA-256 of every other file.
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace axg {

// A buffered file that becomes visible under its name only on commit().
class AtomicFile {
 public:
  // kFile: commit() syncs the file before the rename. kDeferred: commit() starts the
  // write-back and renames without waiting for it; the writer of many files syncs them
  // all at once with sync_filesystem before anything (the manifest) names them.
  enum class Sync { kFile, kDeferred };
  AtomicFile(const std::filesystem::path& dir, const std::string& name, Sync sync = Sync::kFile);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view text);
  // Flushes, syncs and renames into place; returns the hex SHA-256 of the bytes
  // written. Throws RunError on any I/O failure.
  std::string commit();
  std::FILE* handle() { return file_; }
  const std::filesystem::path& final_path() const { return final_; }

 private:
  std::filesystem::path final_, temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
  Sync sync_;
  void* digest_ = nullptr;  // EVP_MD_CTX, hashed as bytes are written
};

// Writes a whole file atomically (AtomicFile, write, commit); returns its SHA-256.
std::string write_file_atomically(const std::filesystem::path& dir, const std::string& name, std::string_view text);

// Syncs the file system that holds dir (syncfs): the deferred AtomicFiles written there
// are on disk when it returns. Throws RunError when it fails.
void sync_filesystem(const std::filesystem::path& dir);

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

// Hex SHA-256 of a file's bytes (OpenSSL EVP).
std::string sha256_file(const std::filesystem::path& path);
std::string sha256_hex(std::string_view bytes);

// Creates the directory if needed; InputError when the path exists and is not a
// directory or cannot be created.
void prepare_output_dir(const std::filesystem::path& dir);

}  // namespace axg
