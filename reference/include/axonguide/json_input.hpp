#pragma once
// Reading JSON that a user wrote (scenes, sweeps): stricter than nlohmann::json::parse, and
// safe to quote back in a message.
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace axg {

// Parses one JSON value and nothing after it but whitespace. Throws InputError, prefixed
// with `origin`, for invalid JSON, for a NUL byte anywhere (nlohmann's lexer would take it
// for the end of the text, so `{}\0...` would pass), and for a key given twice in one object
// (nlohmann keeps the last one), naming its key path: "neurons.region.shape",
// "cues.sources[1].kind". The caller limits the nesting depth first.
nlohmann::json parse_json_strict(const std::string& text, const std::string& origin);

// `text` with every byte that is not printable escaped, so that a message quoting a key or
// a value cannot move the cursor or recolour the terminal: C0 controls and DEL as \u0001,
// C1 controls and the Unicode format characters that reorder or hide text (U+200B-U+200F,
// U+2028-U+202E, U+2060-U+2069, U+FEFF) as \u0085, and bytes that are not UTF-8 as \xff.
// Printable ASCII and other well-formed UTF-8 pass unchanged.
std::string printable(std::string_view text);

}  // namespace axg
