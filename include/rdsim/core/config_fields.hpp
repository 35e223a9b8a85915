#pragma once
#include <concepts>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "rdsim/core/config_reader.hpp"

// One declaration per config key. A config struct lists its keys once, in a `describe` function
// next to the struct:
//
//   template <class V, class C> requires config::Describes<C, PpoConfig>
//   void describe(V& v, C& c) {
//     v.field("n_steps", c.n_steps, config::Range{1, 1'000'000}, "env steps per env per update");
//     v.field("anneal_lr", c.anneal_lr, "linear decay of the learning rate to 0");
//     v.choice("optimizer", c.optimizer, {"rmsprop", "adam"}, "update rule");
//     v.object("cnn", c.cnn, "the convolutional trunk (pixel observations)");
//     v.check(c.kernels.size() == c.channels.size(), "kernels", "expected one kernel per channel");
//   }
//
// and three visitors walk that list: FieldReader (reads JSON through ConfigReader: types, ranges,
// unknown keys, cross-field checks), FieldWriter (the resolved JSON that config.json and model.bin
// record) and FieldDocs (the reference tables in docs/config.md). The default of a key is the
// value the struct starts with, so it is written once too.
namespace rdsim::config {

// `C` is `T` or `const T`: describe() serves readers (mutable) and writers (const) alike.
template <class C, class T>
concept Describes = std::same_as<std::remove_const_t<C>, T>;

template <class T>
struct Range {
  T lo, hi;
};
template <class T>
Range(T, T) -> Range<T>;

// A choice mapped to an enum: {"ground_truth", ObservationMode::GroundTruth}, ...
template <class E>
using Names = std::vector<std::pair<const char*, E>>;

// ---- reading --------------------------------------------------------------------------------

class FieldReader {
public:
  explicit FieldReader(ConfigReader& reader) : r_(reader) {}

  void field(const char* key, bool& v, const char*) { r_.read(key, v); }
  void field(const char* key, std::string& v, const char*) { r_.read(key, v); }
  void field(const char* key, std::uint64_t& v, const char*) { r_.read(key, v); }
  void field(const char* key, int& v, Range<int> r, const char*) { r_.read(key, v, r.lo, r.hi); }
  void field(const char* key, long long& v, Range<long long> r, const char*) { r_.read(key, v, r.lo, r.hi); }
  void field(const char* key, double& v, Range<double> r, const char*) { r_.read(key, v, r.lo, r.hi); }
  void field(const char* key, std::vector<int>& v, Range<int> r, const char*) { r_.read(key, v, r.lo, r.hi); }
  void field(const char* key, std::vector<double>& v, Range<double> r, const char*) { r_.read(key, v, r.lo, r.hi); }
  void field(const char* key, std::vector<std::string>& v, const char*) { r_.read(key, v); }
  void field(const char* key, std::map<std::string, double>& v, Range<double> r, const char*) { r_.read(key, v, r.lo, r.hi); }
  void choice(const char* key, std::string& v, const std::vector<std::string>& choices, const char*) {
    r_.read_choice(key, v, choices);
  }
  template <class E>
  void choice(const char* key, E& v, const Names<E>& names, const char*) {
    std::string text = name_of(v, names);
    std::vector<std::string> choices;
    for (const auto& [name, value] : names) choices.emplace_back(name);
    r_.read_choice(key, text, choices);
    for (const auto& [name, value] : names)
      if (text == name) v = value;
  }
  template <class S>
  void object(const char* key, S& s, const char*) {
    ConfigReader child = r_.child(key);
    FieldReader sub(child);
    describe(sub, s);
    child.finish();
  }
  void check(bool ok, const char* key, const std::string& what) {
    if (!ok) r_.fail(key, what);
  }

  template <class E>
  static std::string name_of(E v, const Names<E>& names) {
    for (const auto& [name, value] : names)
      if (value == v) return name;
    return "?";
  }

private:
  ConfigReader& r_;
};

// Reads the keys of `s` from `reader` over the values `s` already holds (its defaults), then
// rejects keys that `s` does not declare.
template <class S>
void read_fields(ConfigReader& reader, S& s) {
  FieldReader v(reader);
  describe(v, s);
  reader.finish();
}

// ---- writing --------------------------------------------------------------------------------

class FieldWriter {
public:
  explicit FieldWriter(nlohmann::json& out) : out_(out) {}

  template <class T>
  void field(const char* key, const T& v, const char*) {
    out_[key] = v;
  }
  template <class T, class R>
  void field(const char* key, const T& v, R, const char*) {
    out_[key] = v;
  }
  void choice(const char* key, const std::string& v, const std::vector<std::string>&, const char*) { out_[key] = v; }
  template <class E>
  void choice(const char* key, const E& v, const Names<E>& names, const char*) {
    out_[key] = FieldReader::name_of(v, names);
  }
  template <class S>
  void object(const char* key, const S& s, const char*) {
    nlohmann::json sub = nlohmann::json::object();
    FieldWriter w(sub);
    describe(w, s);
    out_[key] = std::move(sub);
  }
  void check(bool, const char*, const std::string&) {}

private:
  nlohmann::json& out_;
};

// Every key of `s` with its value, in declaration order of the keys' first appearance.
template <class S>
nlohmann::json write_fields(const S& s) {
  nlohmann::json out = nlohmann::json::object();
  FieldWriter w(out);
  describe(w, s);
  return out;
}

// ---- documenting ----------------------------------------------------------------------------

// One row of a reference table.
struct FieldDoc {
  std::string key;          // dotted path below the struct ("cnn.preset")
  std::string type;         // "integer", "number", "boolean", "string", "list of integers", ...
  std::string default_value;  // JSON text
  std::string range;        // "1 … 1000000", "`\"tanh\"` | `\"relu\"`" (markdown code), "" when any value goes
  std::string doc;
};

class FieldDocs {
public:
  explicit FieldDocs(std::vector<FieldDoc>& rows, std::string prefix = "") : rows_(rows), prefix_(std::move(prefix)) {}

  void field(const char* key, const bool& v, const char* doc) { add(key, "boolean", v, "", doc); }
  void field(const char* key, const std::string& v, const char* doc) { add(key, "string", v, "", doc); }
  void field(const char* key, const std::uint64_t& v, const char* doc) { add(key, "integer", v, "≥ 0", doc); }
  void field(const char* key, const int& v, Range<int> r, const char* doc) { add(key, "integer", v, range(r), doc); }
  void field(const char* key, const long long& v, Range<long long> r, const char* doc) {
    add(key, "integer", v, range(r), doc);
  }
  void field(const char* key, const double& v, Range<double> r, const char* doc) { add(key, "number", v, range(r), doc); }
  void field(const char* key, const std::vector<int>& v, Range<int> r, const char* doc) {
    add(key, "list of integers", v, "each " + range(r), doc);
  }
  void field(const char* key, const std::vector<double>& v, Range<double> r, const char* doc) {
    add(key, "list of numbers", v, "each " + range(r), doc);
  }
  void field(const char* key, const std::vector<std::string>& v, const char* doc) {
    add(key, "list of strings", v, "", doc);
  }
  void field(const char* key, const std::map<std::string, double>& v, Range<double> r, const char* doc) {
    add(key, "object of numbers", v, "each " + range(r), doc);
  }
  void choice(const char* key, const std::string& v, const std::vector<std::string>& choices, const char* doc) {
    add(key, "string", v, alternatives(choices), doc);
  }
  template <class E>
  void choice(const char* key, const E& v, const Names<E>& names, const char* doc) {
    std::vector<std::string> choices;
    for (const auto& [name, value] : names) choices.emplace_back(name);
    add(key, "string", FieldReader::name_of(v, names), alternatives(choices), doc);
  }
  template <class S>
  void object(const char* key, const S& s, const char*) {
    FieldDocs sub(rows_, prefix_ + key + ".");
    describe(sub, s);
  }
  void check(bool, const char*, const std::string&) {}

private:
  template <class T>
  void add(const char* key, const char* type, const T& v, std::string range_text, const char* doc) {
    rows_.push_back({prefix_ + key, type, nlohmann::json(v).dump(), std::move(range_text), doc});
  }
  template <class T>
  static std::string range(Range<T> r) {
    std::ostringstream os;
    os << r.lo << " … " << r.hi;
    return os.str();
  }
  static std::string alternatives(const std::vector<std::string>& choices) {
    std::string s;
    for (const auto& c : choices) s += (s.empty() ? "" : " | ") + ("`\"" + c + "\"`");
    return s;
  }

  std::vector<FieldDoc>& rows_;
  std::string prefix_;
};

template <class S>
std::vector<FieldDoc> document_fields(const S& s) {
  std::vector<FieldDoc> rows;
  FieldDocs d(rows);
  describe(d, s);
  return rows;
}

}  // namespace rdsim::config
