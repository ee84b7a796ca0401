// The one declaration of a parameter struct's fields, from which its reading (type and range
// checked, unknown keys refused, errors naming the key), its writing (the JSON written next to
// every result), its defaults listing and its docs table are all generated. A field is declared
// once, in one list; nothing else in the code base spells its key.
//
//   // kernel_matcher.cpp
//   const FieldList<KernelMatcherParams>& KernelMatcherParams::fields() {
//     using P = KernelMatcherParams;
//     static const FieldList<P> f = FieldList<P>("matcher kernel")
//         .number("resolution_m", &P::resolution_m, 0.01, 1.0, "grid resolution, m")
//         .integer("blur_size_px", &P::blur_size_px, 0, 101, "RW Gaussian blur kernel size, px (odd, 0 = none)")
//         .choice("line_rule", &P::line_rule, kLineRuleNames, "line rasterisation")
//         .flatten(&P::blocking, blocking_fields())            // its keys at this level
//         .section("scale", &P::scale, scale_fields(), "")     // its keys under "scale": {...}
//         .check([](const P& p, const ParamReader& r) {        // rules across fields
//           if (p.blur_size_px % 2 == 0) r.fail("blur_size_px", "must be odd");
//         });
//     return f;
//   }
//   nlohmann::ordered_json KernelMatcherParams::to_json() const { return fields().write(*this); }
//   void KernelMatcherParams::apply_overrides(const nlohmann::json& o) { fields().read(*this, o); }
//
// The default of a field is the member's initialiser in the struct (the single source); the key
// order of the list is the key order of the written JSON. A member can be named by a member
// pointer or by a callable `[](auto& p) -> auto& { return p.lidar.voxel_plane; }` (nested members).
// `floorcast params` lists every registered parameter set from these lists, and
// docs/parameters.md is generated from them (a test checks it is current).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "floorcast/core/params.hpp"

namespace floorcast {

/// One field as the defaults listing and the docs table show it.
struct FieldInfo {
  std::string key;    ///< dotted inside sections ("scale.min_scale")
  std::string type;   ///< "number", "integer", "non-negative integer", "true/false", "text", "numbers", "a | b | c"
  std::string range;  ///< "[lo, hi]" for numbers, "" otherwise
  std::string doc;    ///< what it is, with its unit and its source (paper section, reference code)
  nlohmann::ordered_json value;  ///< its value in the instance described (the defaults: T{})
};

/// "[lo, hi]" as the docs and the error messages print it.
std::string range_text(double lo, double hi);
std::string range_text(long long lo, long long hi);

/// A Markdown table (key | default | type | allowed | meaning) of `fields`.
std::string fields_markdown(const std::vector<FieldInfo>& fields);

template <class T>
class FieldList {
 public:
  /// `who` names the parameter set in error messages ("matcher kernel", "tracker pf").
  explicit FieldList(std::string who) : who_(std::move(who)) {}

  const std::string& who() const { return who_; }

  /// A finite number in [lo, hi].
  template <class M>
  FieldList& number(const char* key, M member, double lo, double hi, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "number", range_text(lo, hi), doc,
                [get, lo, hi](ParamReader& r, const char* k, T& t) { r.read(k, get(t), lo, hi); });
  }
  /// An integer in [lo, hi].
  template <class M>
  FieldList& integer(const char* key, M member, int lo, int hi, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "integer", range_text(static_cast<long long>(lo), static_cast<long long>(hi)), doc,
                [get, lo, hi](ParamReader& r, const char* k, T& t) { r.read(k, get(t), lo, hi); });
  }
  /// A non-negative 64-bit integer (seeds).
  template <class M>
  FieldList& unsigned_integer(const char* key, M member, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "non-negative integer", "", doc, [get](ParamReader& r, const char* k, T& t) { r.read(k, get(t)); });
  }
  template <class M>
  FieldList& flag(const char* key, M member, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "true/false", "", doc, [get](ParamReader& r, const char* k, T& t) { r.read(k, get(t)); });
  }
  template <class M>
  FieldList& text(const char* key, M member, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "text", "", doc, [get](ParamReader& r, const char* k, T& t) { r.read(k, get(t)); });
  }
  /// A non-empty list of numbers, each in [lo, hi].
  template <class M>
  FieldList& numbers(const char* key, M member, double lo, double hi, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "numbers", range_text(lo, hi), doc,
                [get, lo, hi](ParamReader& r, const char* k, T& t) { r.read(k, get(t), lo, hi); });
  }
  /// A list of strings.
  template <class M>
  FieldList& texts(const char* key, M member, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "texts", "", doc, [get](ParamReader& r, const char* k, T& t) { r.read(k, get(t)); });
  }
  /// A series of finite numbers of any length (empty included): values recorded per step.
  template <class M>
  FieldList& series(const char* key, M member, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "numbers", "", doc, [get](ParamReader& r, const char* k, T& t) { r.read_series(k, get(t)); });
  }
  /// A list of integers of any length.
  template <class M>
  FieldList& integers(const char* key, M member, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "integers", "", doc, [get](ParamReader& r, const char* k, T& t) { r.read(k, get(t)); });
  }
  /// A field whose JSON form is not one of the kinds above: `write(j, value)` sets j[key] (or
  /// more), `read(r, value)` reads it back from the reader.
  FieldList& custom(const char* key, std::function<void(nlohmann::ordered_json&, const T&)> write,
                    std::function<void(ParamReader&, T&)> read, const char* type, const char* doc) {
    Entry e;
    const std::string k = key;
    e.keys = {k};
    e.read = std::move(read);
    e.write = write;
    e.describe = [k, write, type = std::string(type), d = std::string(doc)](const T& t) {
      nlohmann::ordered_json j = nlohmann::ordered_json::object();
      write(j, t);
      return std::vector<FieldInfo>{{k, type, "", d, j.contains(k) ? j[k] : nlohmann::ordered_json()}};
    };
    entries_.push_back(std::move(e));
    return *this;
  }
  /// Any JSON value kept as is (an opaque block, e.g. a stage's overrides as given).
  template <class M>
  FieldList& json(const char* key, M member, const char* doc) {
    auto get = accessor(member);
    return leaf(key, get, "JSON", "", doc, [get](ParamReader& r, const char* k, T& t) { r.read(k, get(t)); });
  }
  /// An enumeration written as one of `names`.
  template <class M, class E>
  FieldList& choice(const char* key, M member, std::vector<std::pair<const char*, E>> names, const char* doc) {
    auto get = accessor(member);
    std::string type;
    for (const auto& [name, v] : names) type += (type.empty() ? "" : " | ") + std::string(name);
    Entry e;
    const std::string k = key;
    e.keys = {k};
    e.read = [get, k, names](ParamReader& r, T& t) { r.read_enum(k.c_str(), get(t), names); };
    e.write = [get, k, names](nlohmann::ordered_json& j, const T& t) { j[k] = enum_name(get(t), names); };
    e.describe = [get, k, names, type, d = std::string(doc)](const T& t) {
      return std::vector<FieldInfo>{{k, type, "", d, enum_name(get(t), names)}};
    };
    entries_.push_back(std::move(e));
    return *this;
  }
  /// The fields of a member struct at this level (its keys beside this struct's own).
  template <class M, class S>
  FieldList& flatten(M member, const FieldList<S>& sub) {
    auto get = accessor(member);
    for (const auto& se : sub.entries_) {
      Entry e;
      e.keys = se.keys;
      e.read = [get, f = se.read](ParamReader& r, T& t) { f(r, get(t)); };
      e.write = [get, f = se.write](nlohmann::ordered_json& j, const T& t) { f(j, get(t)); };
      e.describe = [get, f = se.describe](const T& t) { return f(get(t)); };
      entries_.push_back(std::move(e));
    }
    for (const auto& c : sub.checks_) checks_.push_back([get, c](const T& t, const ParamReader& r) { c(get(t), r); });
    return *this;
  }
  /// The fields of a member struct under `key` ({"key": {...}}; errors name "key.sub").
  template <class M, class S>
  FieldList& section(const char* key, M member, const FieldList<S>& sub) {
    auto get = accessor(member);
    Entry e;
    const std::string k = key;
    e.keys = {k};
    e.read = [get, k, sub](ParamReader& r, T& t) {
      r.section(k.c_str(), [&](ParamReader& in) { sub.read_into(in, get(t)); });
    };
    e.write = [get, k, sub](nlohmann::ordered_json& j, const T& t) { j[k] = sub.write(get(t)); };
    e.describe = [get, k, sub](const T& t) {
      std::vector<FieldInfo> out = sub.describe(get(t));
      for (FieldInfo& f : out) f.key = k + "." + f.key;
      return out;
    };
    entries_.push_back(std::move(e));
    return *this;
  }
  /// A list of member structs (std::vector<S>), each an object with the fields of `sub`.
  template <class M, class S>
  FieldList& list(const char* key, M member, const FieldList<S>& sub) {
    auto get = accessor(member);
    Entry e;
    const std::string k = key;
    e.keys = {k};
    e.read = [get, k, sub](ParamReader& r, T& t) {
      std::vector<S> out;
      if (!r.objects(k.c_str(), [&](ParamReader& in, std::size_t) {
            S item;
            sub.read_into(in, item);
            out.push_back(std::move(item));
          })) {
        return;
      }
      get(t) = std::move(out);
    };
    e.write = [get, k, sub](nlohmann::ordered_json& j, const T& t) {
      nlohmann::ordered_json a = nlohmann::ordered_json::array();
      for (const S& item : get(t)) a.push_back(sub.write(item));
      j[k] = std::move(a);
    };
    e.describe = [k, sub](const T&) {
      std::vector<FieldInfo> out = sub.describe(S{});
      for (FieldInfo& f : out) f.key = k + "[]." + f.key;
      return out;
    };
    entries_.push_back(std::move(e));
    return *this;
  }
  /// The last field is optional: written only when `present(value)` holds, and a record may
  /// leave it out (it keeps its default then).
  FieldList& optional(std::function<bool(const T&)> present) {
    Entry& e = entries_.back();
    e.read = [f = e.read, keys = e.keys](ParamReader& r, T& t) {
      if (r.mode() == ReadMode::kRecord && !r.optional(keys.front().c_str())) return;
      f(r, t);
    };
    e.write = [f = e.write, present](nlohmann::ordered_json& j, const T& t) {
      if (present(t)) f(j, t);
    };
    return *this;
  }
  /// A rule across fields, checked after every field is read (and by validate()): calls
  /// r.fail(key, reason) when broken.
  FieldList& check(std::function<void(const T&, const ParamReader&)> rule) {
    checks_.push_back(std::move(rule));
    return *this;
  }

  /// Applies `overrides` (a JSON object, keys as write() writes them) to `value`: every key is
  /// type- and range-checked, unknown keys are refused, then the rules are checked. Throws
  /// ParameterError naming the key.
  void read(T& value, const nlohmann::json& overrides) const {
    ParamReader r(overrides, who_);
    read_into(r, value);
    r.finish();
  }
  /// Reads a record (a file floorcast wrote): every field must be present (except optional ones),
  /// unknown keys are refused; errors read "<source>: <key>: <reason>".
  void read_record(T& value, const nlohmann::json& j, const std::string& source) const {
    ParamReader r(j, source, "", ReadMode::kRecord);
    read_into(r, value);
    r.finish();
  }
  /// Same, into an open reader (the caller finishes it).
  void read_into(ParamReader& r, T& value) const {
    for (const Entry& e : entries_) e.read(r, value);
    for (const auto& c : checks_) c(value, r);
  }
  /// Every field with its value, in declaration order.
  nlohmann::ordered_json write(const T& value) const {
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    write_into(j, value);
    return j;
  }
  void write_into(nlohmann::ordered_json& j, const T& value) const {
    for (const Entry& e : entries_) e.write(j, value);
  }
  /// Checks the ranges and rules of a value filled in code (as read() would for the same JSON).
  void validate(const T& value) const {
    T copy = value;
    read(copy, nlohmann::json(write(value)));
  }
  /// Every field (sections expanded, dotted keys) with its value in `value`.
  std::vector<FieldInfo> describe(const T& value = T{}) const {
    std::vector<FieldInfo> out;
    for (const Entry& e : entries_) {
      for (FieldInfo& f : e.describe(value)) out.push_back(std::move(f));
    }
    return out;
  }

 private:
  template <class U>
  friend class FieldList;

  struct Entry {
    std::vector<std::string> keys;  ///< the top-level key(s) it reads
    std::function<void(ParamReader&, T&)> read;
    std::function<void(nlohmann::ordered_json&, const T&)> write;
    std::function<std::vector<FieldInfo>(const T&)> describe;
  };

  template <class G>
  static auto accessor(G member) {
    if constexpr (std::is_member_object_pointer_v<G>) {
      return [member](auto& t) -> auto& { return t.*member; };
    } else {
      return member;
    }
  }

  template <class Get, class Read>
  FieldList& leaf(const char* key, Get get, const char* type, std::string range, const char* doc, Read read_fn) {
    Entry e;
    const std::string k = key;
    e.keys = {k};
    e.read = [k, read_fn](ParamReader& r, T& t) { read_fn(r, k.c_str(), t); };
    e.write = [k, get](nlohmann::ordered_json& j, const T& t) { j[k] = get(t); };
    e.describe = [k, get, type = std::string(type), range, d = std::string(doc)](const T& t) {
      return std::vector<FieldInfo>{{k, type, range, d, nlohmann::ordered_json(get(t))}};
    };
    entries_.push_back(std::move(e));
    return *this;
  }

  std::string who_;
  std::vector<Entry> entries_;
  std::vector<std::function<void(const T&, const ParamReader&)>> checks_;
};

/// The one JSON form of blocking flags in parameter sets (flattened into each stage's keys):
/// "doors_closed" (open doors drawn closed), "glass_blocks", "obstacles_block", "cut_height_m".
/// Closed door leaves always block.
const FieldList<BlockingOptions>& blocking_fields();
/// SharedParams: range_m, then the blocking flags.
const FieldList<SharedParams>& shared_fields();

}  // namespace floorcast
