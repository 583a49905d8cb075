#include "axonguide/scene/json_input.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "axonguide/support/error.hpp"

namespace axg {

using nlohmann::json;

namespace {

// Where the parser is: one frame per open object or array.
struct Frame {
  bool object = false;
  std::set<std::string> keys;  // object: the keys seen so far
  std::string key;             // object: the key whose value is being read
  std::size_t index = 0;       // array: the element being read
};

std::string key_path(const std::vector<Frame>& stack) {
  std::string path;
  for (const Frame& f : stack) {
    if (f.object) {
      if (!path.empty()) path += '.';
      path += f.key;
    } else {
      path += fmt::format("[{}]", f.index);
    }
  }
  return path;
}

// A value of the innermost array is complete: the next one has the next index.
void element_done(std::vector<Frame>& stack) {
  if (!stack.empty() && !stack.back().object) ++stack.back().index;
}

bool needs_escape(char32_t c) {
  return c < 0x20 || (c >= 0x7F && c <= 0x9F) || (c >= 0x200B && c <= 0x200F) ||
         (c >= 0x2028 && c <= 0x202E) || (c >= 0x2060 && c <= 0x2069) || c == 0xFEFF;
}

// Length of the well-formed UTF-8 sequence at s[i] (RFC 3629: no overlong forms, no
// surrogates, at most U+10FFFF) with its code point, or 0.
std::size_t utf8_sequence(std::string_view s, std::size_t i, char32_t& cp) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[i + k]); };
  const unsigned char c = b(0);
  std::size_t len;
  char32_t min;
  if (c < 0x80) { cp = c; return 1; }
  if (c >= 0xC2 && c <= 0xDF) len = 2, cp = c & 0x1F, min = 0x80;
  else if (c >= 0xE0 && c <= 0xEF) len = 3, cp = c & 0x0F, min = 0x800;
  else if (c >= 0xF0 && c <= 0xF4) len = 4, cp = c & 0x07, min = 0x10000;
  else return 0;
  if (i + len > s.size()) return 0;
  for (std::size_t k = 1; k < len; ++k) {
    if ((b(k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b(k) & 0x3F);
  }
  if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return len;
}

}  // namespace

namespace {

void check_nesting(const std::string& text, const std::string& origin, int max_depth) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (char ch : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (ch == '\\') escaped = true;
      else if (ch == '"') in_string = false;
      continue;
    }
    if (ch == '"') in_string = true;
    else if (ch == '{' || ch == '[') {
      if (++depth > max_depth) throw InputError(fmt::format("{}: JSON nested deeper than {} levels", origin, max_depth));
    } else if (ch == '}' || ch == ']') --depth;
  }
}

}  // namespace

std::string read_input_file(const std::string& path, const std::string& what, std::size_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(fmt::format("{} {}: cannot open: {}", what, path, std::strerror(errno)));
  if (S_ISDIR(st.st_mode)) throw InputError(fmt::format("{} {}: is a directory, not a file", what, path));
  if (!S_ISREG(st.st_mode)) throw InputError(fmt::format("{} {}: not a regular file", what, path));
  if (static_cast<std::size_t>(st.st_size) > max_bytes)
    throw InputError(fmt::format("{} {}: {} bytes is too large (limit {})", what, path, st.st_size, max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{} {}: cannot read: {}", what, path, std::strerror(errno)));
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("{} {}: read error", what, path));
  return buf.str();
}

json parse_json_strict(const std::string& text, const std::string& origin, int max_depth) {
  check_nesting(text, origin, max_depth);
  if (const void* nul = std::memchr(text.data(), '\0', text.size())) {
    const std::size_t at = static_cast<std::size_t>(static_cast<const char*>(nul) - text.data());
    std::size_t line = 1, column = 1;
    for (std::size_t k = 0; k < at; ++k) {
      if (text[k] == '\n') ++line, column = 1;
      else ++column;
    }
    throw InputError(fmt::format("{}: not valid JSON: a NUL byte at line {}, column {} (byte {}); JSON is text",
                                 origin, line, column, at));
  }
  std::vector<Frame> stack;
  const json::parser_callback_t watch = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start: stack.push_back({true, {}, {}, 0}); break;
      case json::parse_event_t::array_start: stack.push_back({false, {}, {}, 0}); break;
      case json::parse_event_t::key: {
        Frame& f = stack.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second)
          throw InputError(fmt::format("{}: duplicate key {}: a key may appear only once in an object",
                                       origin, key_path(stack)));
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        stack.pop_back();
        element_done(stack);
        break;
      case json::parse_event_t::value: element_done(stack); break;
    }
    return true;
  };
  try {
    return json::parse(text, watch);
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", origin, e.what()));
  }
}

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    char32_t cp = 0;
    const std::size_t len = utf8_sequence(text, i, cp);
    if (len == 0) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text[i]));
      ++i;
      continue;
    }
    if (needs_escape(cp)) out += fmt::format("\\u{:04x}", static_cast<std::uint32_t>(cp));
    else out.append(text.substr(i, len));
    i += len;
  }
  return out;
}

}  // namespace axg
