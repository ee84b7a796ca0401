#include "floorcast/core/json_text.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unordered_set>
#include <vector>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

/// Length of the valid UTF-8 sequence starting at s[i], 0 when the byte there starts none.
std::size_t utf8_sequence(const std::string& s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c == 0xE0) n = 3, lo = 0xA0;
  else if ((c >= 0xE1 && c <= 0xEC) || c == 0xEE || c == 0xEF) n = 3;
  else if (c == 0xED) n = 3, hi = 0x9F;  // no UTF-16 surrogates
  else if (c == 0xF0) n = 4, lo = 0x90;
  else if (c >= 0xF1 && c <= 0xF3) n = 4;
  else if (c == 0xF4) n = 4, hi = 0x8F;  // nothing above U+10FFFF
  else return 0;
  if (i + n > s.size()) return 0;
  if (b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  }
  return n;
}

struct TooDeep {};
struct DuplicateKey {
  std::string key;
};

/// Where the second occurrence of a key in one object is (the duplicate the parser met first), or
/// npos: a scan over the text tracking each open object's keys as written.
std::size_t locate_duplicate_key(const std::string& text) {
  std::vector<std::vector<std::string>> objects;  // keys of each open container (arrays: unused)
  std::vector<bool> is_object;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '{' || c == '[') {
      is_object.push_back(c == '{');
      objects.emplace_back();
    } else if (c == '}' || c == ']') {
      if (!objects.empty()) {
        objects.pop_back();
        is_object.pop_back();
      }
    } else if (c == '"') {
      std::size_t j = i + 1;
      while (j < text.size() && text[j] != '"') j += text[j] == '\\' ? 2 : 1;
      const std::string token = text.substr(i + 1, std::min(j, text.size()) - i - 1);
      std::size_t k = j + 1;
      while (k < text.size() && std::isspace(static_cast<unsigned char>(text[k]))) ++k;
      if (k < text.size() && text[k] == ':' && !is_object.empty() && is_object.back()) {
        std::vector<std::string>& keys = objects.back();
        if (std::find(keys.begin(), keys.end(), token) != keys.end()) return i;
        keys.push_back(token);
      }
      i = j;
    }
  }
  return std::string::npos;
}

/// Where a parse that the callback stopped went wrong: the first container opened deeper than
/// `max_depth` (depth_problem) or the first number that overflows a double. npos when neither.
std::size_t locate_problem(const std::string& text, long max_depth, bool& depth_problem) {
  long depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        depth_problem = true;
        return i;
      }
    } else if (c == ']' || c == '}') {
      --depth;
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      std::size_t j = i;
      while (j < text.size() && (std::isdigit(static_cast<unsigned char>(text[j])) || text[j] == '-' ||
                                 text[j] == '+' || text[j] == '.' || text[j] == 'e' || text[j] == 'E')) {
        ++j;
      }
      const std::string token = text.substr(i, j - i);
      errno = 0;
      const double v = std::strtod(token.c_str(), nullptr);
      if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1.0)) {
        depth_problem = false;
        return i;
      }
      i = j - 1;
    }
  }
  return std::string::npos;
}

std::string position(const std::string& text, std::size_t offset) {
  std::size_t line = 0, column = 0;
  line_column(text, offset, line, column);
  return std::to_string(line) + ":" + std::to_string(column);
}

/// nlohmann's DOM builder with a nesting limit enforced as containers open (the SAX route: the
/// parser callback's DOM builder rescans the parent container at every closing brace, quadratic
/// in the length of an array of objects).
template <class J>
class DepthLimitedDom : public nlohmann::detail::json_sax_dom_parser<J> {
  using Base = nlohmann::detail::json_sax_dom_parser<J>;

 public:
  DepthLimitedDom(J& root, long max_depth) : Base(root, true), max_depth_(max_depth) {}
  bool start_object(std::size_t n) {
    if (++depth_ > max_depth_) throw TooDeep{};
    keys_.emplace_back();
    return Base::start_object(n);
  }
  bool end_object() {
    --depth_;
    keys_.pop_back();
    return Base::end_object();
  }
  bool start_array(std::size_t n) {
    if (++depth_ > max_depth_) throw TooDeep{};
    return Base::start_array(n);
  }
  bool end_array() {
    --depth_;
    return Base::end_array();
  }
  /// JSON allows a key twice in one object and nlohmann keeps the last: refused, so no value is
  /// silently dropped (and no error blames the wrong one).
  bool key(typename J::string_t& k) {
    if (!keys_.empty() && !keys_.back().insert(k).second) throw DuplicateKey{k};
    return Base::key(k);
  }

 private:
  long max_depth_;
  long depth_ = 0;
  std::vector<std::unordered_set<std::string>> keys_;
};

template <class J>
J parse_impl(const std::string& text, const std::string& source) {
  const double limit = input_limits().max_nesting_depth;
  const long max_depth = limit >= 1e9 ? 1000000000L : static_cast<long>(limit);
  try {
    J result;
    DepthLimitedDom<J> sax(result, max_depth);
    J::sax_parse(text, &sax, nlohmann::detail::input_format_t::json, /*strict=*/true, /*ignore_comments=*/false);
    return result;
  } catch (const TooDeep&) {
    bool depth_problem = true;
    const std::size_t at = locate_problem(text, max_depth, depth_problem);
    throw LimitError(source + (at == std::string::npos ? std::string() : ":" + position(text, at)) +
                         ": nesting deeper than " + std::to_string(max_depth) +
                         " levels exceeds the limit max_nesting_depth (raise it with "
                         "FLOORCAST_LIMITS=max_nesting_depth=N; docs/limits.md)",
                     "max_nesting_depth");
  } catch (const DuplicateKey& d) {
    const std::size_t at = locate_duplicate_key(text);
    throw InputError(source + (at == std::string::npos ? std::string() : ":" + position(text, at)) + ": duplicate key \"" +
                     printable_text(d.key, 80) + "\" in one object (JSON keeps only one of them; remove the other)");
  } catch (const nlohmann::json::parse_error& e) {
    std::string reason = e.what();
    const auto cut = reason.find(": ", reason.find("column"));
    if (reason.find("column") != std::string::npos && cut != std::string::npos) reason = reason.substr(cut + 2);
    const std::size_t at = e.byte > 0 ? std::min<std::size_t>(e.byte - 1, text.size()) : 0;
    throw InputError(source + ":" + position(text, at) + ": malformed JSON: " + printable_text(reason));
  } catch (const nlohmann::json::exception& e) {
    // out_of_range.406: a number that does not fit a double.
    bool depth_problem = false;
    const std::size_t at = locate_problem(text, max_depth, depth_problem);
    std::string reason = e.what();
    const auto cut = reason.find("] ");
    if (cut != std::string::npos) reason = reason.substr(cut + 2);
    throw InputError(source + (at == std::string::npos ? std::string() : ":" + position(text, at)) +
                     ": malformed JSON: " + printable_text(reason));
  }
}

template <class J>
std::string excerpt_impl(const J& value, std::size_t max_chars) {
  std::string s = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (s.size() > max_chars) {
    std::size_t cut = max_chars;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // whole code points
    s = s.substr(0, cut) + "...";
  }
  return s;
}

}  // namespace

nlohmann::json parse_json_text(const std::string& text, const std::string& source) {
  return parse_impl<nlohmann::json>(text, source);
}

nlohmann::ordered_json parse_ordered_json_text(const std::string& text, const std::string& source) {
  return parse_impl<nlohmann::ordered_json>(text, source);
}

nlohmann::json read_json_file(const std::string& path) { return parse_json_text(read_text_file(path), input_name(path)); }

bool strip_utf8_bom(std::string& text) {
  if (text.size() < 3 || text.compare(0, 3, "\xEF\xBB\xBF") != 0) return false;
  text.erase(0, 3);
  return true;
}

std::string json_excerpt(const nlohmann::json& value, std::size_t max_chars) { return excerpt_impl(value, max_chars); }
std::string json_excerpt(const nlohmann::ordered_json& value, std::size_t max_chars) {
  return excerpt_impl(value, max_chars);
}

std::string printable_text(const std::string& text, std::size_t max_chars) {
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const std::size_t n = utf8_sequence(text, i);
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (n == 0 || (n == 1 && (c < 0x20 || c == 0x7F))) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
      ++i;
    } else {
      out.append(text, i, n);
      i += n;
    }
  }
  return out;
}

bool valid_utf8(const std::string& text, std::size_t* bad_offset) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_sequence(text, i);
    if (n == 0) {
      if (bad_offset) *bad_offset = i;
      return false;
    }
    i += n;
  }
  return true;
}

void line_column(const std::string& text, std::size_t offset, std::size_t& line, std::size_t& column) {
  line = 1;
  column = 1;
  const std::size_t end = std::min(offset, text.size());
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
      ++column;
    }
  }
}

}  // namespace floorcast
