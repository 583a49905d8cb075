#pragma once
// The two ways a run can refuse, with the exit codes of SPEC §4:
//   InputError (exit 2): the scene or a flag is wrong; the message names the key path,
//                        the value and what is allowed.
//   RunError   (exit 3): the input is valid but the run cannot proceed (packing too
//                        dense, memory estimate above the machine's, no usable GPU).
#include <cstdint>
#include <stdexcept>
#include <string>

namespace axg {

inline constexpr int kExitOk = 0;
inline constexpr int kExitCheckFailed = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitCannotRun = 3;

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  // A scene error also names its parts: the key path ("cues.sources[2].kd"), the value as
  // written, and what is allowed (the Python module's SceneError carries them).
  InputError(const std::string& message, std::string key, std::string value, std::string allowed)
      : std::runtime_error(message), key_(std::move(key)), value_(std::move(value)), allowed_(std::move(allowed)) {}
  const std::string& key() const { return key_; }
  const std::string& value() const { return value_; }
  const std::string& allowed() const { return allowed_; }

 private:
  std::string key_, value_, allowed_;
};

class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bytes of physical memory on this machine (0 when unknown).
std::uint64_t physical_memory_bytes();

// Bytes this process may still allocate: the machine's memory, or less under an address
// space limit (ulimit -v, RLIMIT_AS) after what the process already maps. Sets `why` to
// what limits it.
std::uint64_t usable_memory_bytes(std::string* why = nullptr);

// Throws RunError when `bytes` exceeds usable_memory_bytes(); `what` names the work.
void check_memory_estimate(std::uint64_t bytes, const std::string& what);

std::string human_bytes(double bytes);

// Peak resident memory of this process so far (VmHWM; 0 when unknown).
std::uint64_t peak_rss_bytes();

}  // namespace axg
