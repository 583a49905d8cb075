#include "axonguide/scene/reader.hpp"

#include <cstring>

#include <fmt/format.h>

#include "axonguide/support/error.hpp"

namespace axg {

using nlohmann::json;

std::string show_value(const json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string join_key_path(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

void fail_key(const std::string& path, const json& value, const std::string& allowed) {
  throw InputError(fmt::format("scene: {} = {}: {}", path, show_value(value), allowed), path, show_value(value), allowed);
}

std::string Range::text() const {
  const bool has_lo = lo != -HUGE_VAL, has_hi = hi != HUGE_VAL;
  if (has_lo && has_hi) return fmt::format("must be in {}{}, {}{}", lo_open ? '(' : '[', lo, hi, hi_open ? ')' : ']');
  if (has_lo) return fmt::format("must be {} {}", lo_open ? ">" : ">=", lo);
  if (has_hi) return fmt::format("must be {} {}", hi_open ? "<" : "<=", hi);
  return "must be a finite number";
}

bool Range::contains(double v) const {
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

ObjectReader::ObjectReader(const json& j, std::string path) : j_(j), path_(std::move(path)) {
  if (!j_.is_object()) fail_key(path_.empty() ? "(scene)" : path_, j_, "must be a JSON object");
}

const json* ObjectReader::take(const char* key) {
  bool seen = false;
  for (const char* k : allowed_) seen = seen || std::strcmp(k, key) == 0;
  if (!seen) allowed_.push_back(key);
  auto it = j_.find(key);
  return it == j_.end() ? nullptr : &*it;
}

void ObjectReader::number(const char* key, double& out, Range range) {
  if (const json* v = take(key)) out = read_number(*v, path(key), range);
}

void ObjectReader::optional_number(const char* key, std::optional<double>& out, Range range) {
  if (const json* v = take(key)) {
    if (v->is_null()) out.reset();
    else out = read_number(*v, path(key), range);
  }
}

void ObjectReader::boolean(const char* key, bool& out) {
  if (const json* v = take(key)) {
    if (!v->is_boolean()) fail_key(path(key), *v, "must be true or false");
    out = v->get<bool>();
  }
}

void ObjectReader::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it) {
    bool known = false;
    for (const char* k : allowed_) known = known || it.key() == k;
    if (!known) {
      std::string list;
      for (const char* k : allowed_) list += fmt::format("{}{}", list.empty() ? "" : ", ", k);
      throw InputError(fmt::format("scene: unknown key {} (allowed here: {})", join_key_path(path_, it.key()), list),
                       join_key_path(path_, it.key()), show_value(it.value()), "one of the keys " + list);
    }
  }
}

double ObjectReader::read_number(const json& v, const std::string& path, Range range) {
  if (!v.is_number()) fail_key(path, v, "must be a number; " + range.text());
  double x = v.get<double>();
  if (!std::isfinite(x)) fail_key(path, v, "must be finite; " + range.text());
  if (!range.contains(x)) fail_key(path, v, range.text());
  return x;
}

std::uint64_t ObjectReader::read_integer(const json& v, const std::string& path, std::uint64_t lo, std::uint64_t hi) {
  const std::string allowed = fmt::format("must be an integer in [{}, {}]", lo, hi);
  if (v.is_number_unsigned()) {
    std::uint64_t x = v.get<std::uint64_t>();
    if (x < lo || x > hi) fail_key(path, v, allowed);
    return x;
  }
  if (v.is_number_integer()) fail_key(path, v, allowed);  // negative (non-negative ones are number_unsigned)
  if (!v.is_number_float()) fail_key(path, v, allowed);
  double x = v.get<double>();
  if (!std::isfinite(x) || x != std::floor(x) || x < static_cast<double>(lo) || x > static_cast<double>(hi) ||
      x >= 18446744073709551616.0)
    fail_key(path, v, allowed);
  return static_cast<std::uint64_t>(x);
}

core::Vec3 read_position(const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3) fail_key(path, v, "must be [x, y, z] or null");
  double c[3];
  // + 0.0 turns -0 into +0: one position, one canonical form and one sort key.
  for (int k = 0; k < 3; ++k) c[k] = ObjectReader::read_number(v[k], fmt::format("{}[{}]", path, k), Range{}) + 0.0;
  return {c[0], c[1], c[2]};
}

}  // namespace axg
