// The one way floorcast turns text into JSON values: nesting depth bounded while parsing
// (input_limits().max_nesting_depth, checked by a SAX handler as each container opens, so a
// 100,000-deep document is refused before anything recurses over it), numbers out of range, syntax errors and
// invalid UTF-8 reported as InputError with file:line:column, never as a library exception.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace floorcast {

/// Parses JSON text; `source` names the file in errors ("plan.json:3:17: malformed JSON: ...").
nlohmann::json parse_json_text(const std::string& text, const std::string& source);
nlohmann::ordered_json parse_ordered_json_text(const std::string& text, const std::string& source);

/// Reads and parses a JSON file (size bounded by max_file_bytes).
nlohmann::json read_json_file(const std::string& path);

/// A short, printable form of a value for error messages: compact JSON, invalid UTF-8 replaced,
/// cut to about `max_chars` characters ("[1,2,3,...]").
std::string json_excerpt(const nlohmann::json& value, std::size_t max_chars = 60);
std::string json_excerpt(const nlohmann::ordered_json& value, std::size_t max_chars = 60);

/// `text` with every byte that is not part of valid UTF-8, and every control character, shown as
/// \xNN, cut to about `max_chars` characters: safe to print and to put into JSON.
std::string printable_text(const std::string& text, std::size_t max_chars = 200);

/// True when `text` is valid UTF-8 (no overlong forms, no surrogates, nothing above U+10FFFF).
/// `bad_offset` receives the offset of the first invalid byte.
bool valid_utf8(const std::string& text, std::size_t* bad_offset = nullptr);

/// Removes a UTF-8 byte-order mark (EF BB BF, written by Excel and Windows editors) from the
/// start of `text`; returns whether there was one. Text readers (CSV, TUM, steps.csv) call it so
/// the mark does not glue itself to the first number (JSON, YAML and XML parsers skip it).
bool strip_utf8_bom(std::string& text);

/// 1-based line and column of byte `offset` in `text`.
void line_column(const std::string& text, std::size_t offset, std::size_t& line, std::size_t& column);

}  // namespace floorcast
