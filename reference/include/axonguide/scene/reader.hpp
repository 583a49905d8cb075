#pragma once
// Reading one object of a scene strictly (SPEC §5): every key optional, unknown keys
// refused with the list of the allowed ones, values range-checked; a bad value raises
// InputError naming its key path, the value and what is allowed. The scene's parser and
// every model component's reader (model/*.cpp) read their keys through it.
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "axonguide/core/vec3.hpp"

namespace axg {

// A value quoted in a message: its JSON text, cut at 60 characters.
std::string show_value(const nlohmann::json& v);
std::string join_key_path(const std::string& path, const std::string& key);
// Throws InputError "scene: PATH = VALUE: ALLOWED".
[[noreturn]] void fail_key(const std::string& path, const nlohmann::json& value, const std::string& allowed);

// An allowed numeric interval, printed the way a user reads it.
struct Range {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  bool lo_open = false, hi_open = false;
  std::string text() const;
  bool contains(double v) const;
};
inline Range positive() { return {0, HUGE_VAL, true, false}; }
inline Range non_negative() { return {0, HUGE_VAL, false, false}; }
inline Range closed(double lo, double hi) { return {lo, hi, false, false}; }

// Reads one JSON object, remembering which keys were consumed so that unknown keys can be
// reported with the list of allowed ones.
class ObjectReader {
 public:
  ObjectReader(const nlohmann::json& j, std::string path);

  // The value of `key`, or null when absent; the key becomes allowed.
  const nlohmann::json* take(const char* key);
  std::string path(const char* key) const { return join_key_path(path_, key); }

  void number(const char* key, double& out, Range range);
  void optional_number(const char* key, std::optional<double>& out, Range range);
  template <class Int>
  void integer(const char* key, Int& out, std::uint64_t lo, std::uint64_t hi) {
    if (const nlohmann::json* v = take(key)) out = static_cast<Int>(read_integer(*v, path(key), lo, hi));
  }
  void boolean(const char* key, bool& out);
  template <class E>
  void choice(const char* key, E& out, std::initializer_list<std::pair<const char*, E>> names) {
    const nlohmann::json* v = take(key);
    if (!v) return;
    std::string allowed;
    for (auto& [name, value] : names) {
      if (v->is_string() && v->template get<std::string>() == name) {
        out = value;
        return;
      }
      allowed += std::string(allowed.empty() ? "" : ", ") + "\"" + name + "\"";
    }
    fail_key(path(key), *v, "must be one of " + allowed);
  }

  // Reports the first key that was never taken.
  void finish() const;

  static double read_number(const nlohmann::json& v, const std::string& path, Range range);
  // Integers are compared exactly (a 64-bit seed does not fit a double); a float is
  // accepted when it is integral, so that 1e6 means 1000000.
  static std::uint64_t read_integer(const nlohmann::json& v, const std::string& path, std::uint64_t lo,
                                    std::uint64_t hi);

 private:
  const nlohmann::json& j_;
  std::string path_;
  std::vector<const char*> allowed_;
};

// [x, y, z] of finite numbers (-0 read as +0: one position, one canonical form).
core::Vec3 read_position(const nlohmann::json& v, const std::string& path);

}  // namespace axg
