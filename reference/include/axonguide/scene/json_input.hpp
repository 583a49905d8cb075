#pragma once
// Reading JSON that a user wrote (scenes, sweeps): stricter than nlohmann::json::parse, and
// safe to quote back in a message.
#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace axg {

// Parses one JSON value and nothing after it but whitespace. Throws InputError, prefixed
// with `origin`, for invalid JSON, for a NUL byte anywhere (nlohmann's lexer would take it
// for the end of the text, so `{}\0...` would pass), and for a key given twice in one object
// (nlohmann keeps the last one), naming its key path: "neurons.region.shape",
// "cues.sources[1].kind", and for nesting deeper than `max_depth` (checked before the parser
// sees the text, which recurses once a level: a hostile file cannot exhaust the stack).
inline constexpr int kMaxJsonNesting = 64;  // a scene needs 5 levels, a sweep or a manifest about 10
nlohmann::json parse_json_strict(const std::string& text, const std::string& origin, int max_depth = kMaxJsonNesting);

// The bytes of a file the user named as input: a regular file (not a folder, a device or a
// pipe) of at most max_bytes. Throws InputError "WHAT PATH: why" otherwise.
std::string read_input_file(const std::string& path, const std::string& what, std::size_t max_bytes = 16u << 20);

// `text` with every byte that is not printable escaped, so that a message quoting a key or
// a value cannot move the cursor or recolour the terminal: C0 controls and DEL as \u0001,
// C1 controls and the Unicode format characters that reorder or hide text (U+200B-U+200F,
// U+2028-U+202E, U+2060-U+2069, U+FEFF) as \u0085, and bytes that are not UTF-8 as \xff.
// Printable ASCII and other well-formed UTF-8 pass unchanged.
std::string printable(std::string_view text);

}  // namespace axg
