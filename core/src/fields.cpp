#include "floorcast/core/fields.hpp"

namespace floorcast {
namespace {

/// A Markdown table cell: pipes escaped, no line breaks.
std::string cell(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

}  // namespace

std::string range_text(double lo, double hi) {
  return "[" + nlohmann::json(lo).dump() + ", " + nlohmann::json(hi).dump() + "]";
}

std::string range_text(long long lo, long long hi) { return "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]"; }

std::string fields_markdown(const std::vector<FieldInfo>& fields) {
  std::string out = "| key | default | type | allowed | meaning |\n|---|---|---|---|---|\n";
  for (const FieldInfo& f : fields) {
    out += "| `" + f.key + "` | `" + cell(f.value.dump()) + "` | " + cell(f.type) + " | " + cell(f.range) + " | " +
           cell(f.doc) + " |\n";
  }
  return out;
}

}  // namespace floorcast
