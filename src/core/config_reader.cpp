#include "rdsim/core/config_reader.hpp"

#include <nlohmann/json.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <optional>

#include "rdsim/core/error.hpp"
#include "rdsim/core/json_text.hpp"
#include "rdsim/core/suggest.hpp"

namespace rdsim {
namespace {

std::string describe(const nlohmann::json& v) { return json_excerpt(v, 60); }

// Numbers as people read them: 1e12 rather than 1000000000000, 2^64 - 1 rather than 20 digits;
// plain digits when a short form would not be exact.
std::string readable(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  if (std::strtod(buf, nullptr) != x) std::snprintf(buf, sizeof buf, "%.17g", x);
  std::string s = buf;
  const auto e = s.find("e");  // "1e+12" -> "1e12", "1e-05" -> "1e-5"
  if (e != std::string::npos) {
    std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
    const bool negative = exponent[0] == '-';
    exponent = exponent.substr(1);
    while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
    s = mantissa + "e" + (negative ? "-" : "") + exponent;
  }
  return s;
}
std::string readable(long long x) {
  if (x > -1'000'000 && x < 1'000'000) return std::to_string(x);
  const std::string s = readable(static_cast<double>(x));
  const double back = std::strtod(s.c_str(), nullptr);
  const bool exact = back > -9.2e18 && back < 9.2e18 && std::llround(back) == x;
  return exact && s.size() < std::to_string(x).size() ? s : std::to_string(x);
}
std::string readable(int x) { return std::to_string(x); }

template <class T>
std::string range_text(T lo, T hi) {
  return "in [" + readable(lo) + ", " + readable(hi) + "]";
}

// The integer a JSON number stands for when it is one in [lo, hi] (2, 2.0, 1e5); nullopt otherwise.
std::optional<long long> integer_in(const nlohmann::json& v, long long lo, long long hi) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<long long>::max())) return std::nullopt;
    const auto x = static_cast<long long>(u);
    return x >= lo && x <= hi ? std::optional<long long>(x) : std::nullopt;
  }
  if (v.is_number_integer()) {
    const auto x = v.get<long long>();
    return x >= lo && x <= hi ? std::optional<long long>(x) : std::nullopt;
  }
  if (v.is_number_float()) {
    // Range first: casting a double outside long long's range is undefined.
    const double d = v.get<double>();
    if (!(d >= static_cast<double>(lo) && d <= static_cast<double>(hi)) || std::trunc(d) != d) return std::nullopt;
    const auto x = static_cast<long long>(d);
    return x >= lo && x <= hi ? std::optional<long long>(x) : std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

nlohmann::json json_from_option(const std::string& text) {
  const bool numeric = !text.empty() && text.size() < 64 && text.find_first_not_of("+-.0123456789eE") == std::string::npos;
  if (numeric) {
    const auto parsed = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (parsed.is_number()) return parsed;
  }
  return text;
}

ConfigReader::ConfigReader(const nlohmann::json& object, std::string where, std::string path)
    : object_(object), where_(std::move(where)), path_(std::move(path)) {
  if (!object_.is_object()) {
    throw Error(where_ + ": " + (path_.empty() ? std::string("top level") : path_) +
                ": expected a JSON object, got " + describe(object_));
  }
}

std::string ConfigReader::name(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void ConfigReader::fail(const std::string& key, const std::string& what) const {
  throw Error(where_ + ": " + name(key) + ": " + what);
}

bool ConfigReader::has(const std::string& key) const { return object_.contains(key); }

std::vector<std::string> ConfigReader::keys() const {
  std::vector<std::string> out;
  for (auto it = object_.begin(); it != object_.end(); ++it) out.push_back(it.key());
  return out;
}

const nlohmann::json* ConfigReader::find(const std::string& key) {
  seen_.insert(key);
  auto it = object_.find(key);
  return it == object_.end() ? nullptr : &*it;
}

void ConfigReader::accept(const std::string& key) { seen_.insert(key); }

void ConfigReader::read(const std::string& key, bool& out) {
  const auto* v = find(key);
  if (!v) return;
  if (!v->is_boolean()) fail(key, "expected true or false, got " + describe(*v));
  out = v->get<bool>();
}

namespace {

// Config strings are names and paths: bounded, and no control characters (a NUL would cut a
// path short, a newline would split a message).
bool plain_string(const nlohmann::json& v) {
  if (!v.is_string() || v.get_ref<const std::string&>().size() > max_string_bytes) return false;
  for (const char c : v.get_ref<const std::string&>())
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return false;
  return true;
}

const std::string plain_string_text =
    "at most " + std::to_string(max_string_bytes) + " bytes without control characters";

}  // namespace

void ConfigReader::read(const std::string& key, std::string& out) {
  const auto* v = find(key);
  if (!v) return;
  if (!plain_string(*v)) fail(key, "expected a string of " + plain_string_text + ", got " + describe(*v));
  out = v->get<std::string>();
}

void ConfigReader::read(const std::string& key, std::vector<std::string>& out) {
  const auto* v = find(key);
  if (!v) return;
  const std::string expected =
      "expected a list of at most " + std::to_string(max_list_items) + " strings of " + plain_string_text;
  if (!v->is_array() || v->size() > max_list_items) fail(key, expected + ", got " + describe(*v));
  std::vector<std::string> result;
  for (const auto& e : *v) {
    if (!plain_string(e)) fail(key, expected + ", got " + describe(e) + " in " + describe(*v));
    result.push_back(e.get<std::string>());
  }
  out = std::move(result);
}

void ConfigReader::read(const std::string& key, long long& out, long long lo, long long hi) {
  const auto* v = find(key);
  if (!v) return;
  const auto x = integer_in(*v, lo, hi);
  if (!x) fail(key, "expected an integer " + range_text(lo, hi) + ", got " + describe(*v));
  out = *x;
}

void ConfigReader::read(const std::string& key, int& out, int lo, int hi) {
  long long x = out;
  read(key, x, lo, hi);
  out = static_cast<int>(x);
}

void ConfigReader::read(const std::string& key, std::uint64_t& out) {
  const auto* v = find(key);
  if (!v) return;
  if (v->is_number_unsigned()) {
    out = v->get<std::uint64_t>();
    return;
  }
  const auto x = integer_in(*v, 0, std::numeric_limits<long long>::max());
  if (!x) fail(key, "expected an integer in [0, 2^64 - 1], got " + describe(*v));
  out = static_cast<std::uint64_t>(*x);
}

void ConfigReader::read(const std::string& key, double& out, double lo, double hi) {
  const auto* v = find(key);
  if (!v) return;
  if (!v->is_number()) fail(key, "expected a number " + range_text(lo, hi) + ", got " + describe(*v));
  double x = v->get<double>();
  if (!(x >= lo && x <= hi)) fail(key, "expected a number " + range_text(lo, hi) + ", got " + describe(*v));
  out = x;
}

void ConfigReader::read(const std::string& key, std::vector<int>& out, int lo, int hi) {
  const auto* v = find(key);
  if (!v) return;
  const std::string expected = "expected a list of at most " + std::to_string(max_list_items) + " integers " + range_text(lo, hi);
  if (!v->is_array() || v->size() > max_list_items) fail(key, expected + ", got " + describe(*v));
  std::vector<int> result;
  for (const auto& e : *v) {
    const auto x = integer_in(e, lo, hi);
    if (!x) fail(key, expected + ", got " + describe(e) + " in " + describe(*v));
    result.push_back(static_cast<int>(*x));
  }
  out = std::move(result);
}

void ConfigReader::read(const std::string& key, std::vector<double>& out, double lo, double hi) {
  const auto* v = find(key);
  if (!v) return;
  const std::string expected = "expected a list of at most " + std::to_string(max_list_items) + " numbers " + range_text(lo, hi);
  if (!v->is_array() || v->size() > max_list_items) fail(key, expected + ", got " + describe(*v));
  std::vector<double> result;
  for (const auto& e : *v) {
    if (!e.is_number() || !(e.get<double>() >= lo && e.get<double>() <= hi))
      fail(key, expected + ", got " + describe(e) + " in " + describe(*v));
    result.push_back(e.get<double>());
  }
  out = std::move(result);
}

void ConfigReader::read(const std::string& key, std::map<std::string, double>& out, double lo, double hi) {
  const auto* v = find(key);
  if (!v) return;
  const std::string expected = "expected an object of at most " + std::to_string(max_list_items) +
                               " names, each with a number " + range_text(lo, hi);
  if (!v->is_object() || v->size() > max_list_items) fail(key, expected + ", got " + describe(*v));
  std::map<std::string, double> result;
  for (const auto& [name, e] : v->items()) {
    if (name.empty() || name.size() > max_string_bytes) fail(key, expected + ", got the name " + describe(nlohmann::json(name)));
    if (!e.is_number() || !(e.get<double>() >= lo && e.get<double>() <= hi))
      fail(key + "." + name, "expected a number " + range_text(lo, hi) + ", got " + describe(e));
    result[name] = e.get<double>();
  }
  out = std::move(result);
}

void ConfigReader::read_choice(const std::string& key, std::string& out,
                               const std::vector<std::string>& choices) {
  std::string value = out;
  read(key, value);
  for (const auto& c : choices) {
    if (c == value) {
      out = value;
      return;
    }
  }
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + ("\"" + c + "\"");
  fail(key, "expected one of " + list + ", got " + describe(nlohmann::json(value)) + did_you_mean(value, choices));
}

ConfigReader ConfigReader::child(const std::string& key) {
  const auto* v = find(key);
  static const nlohmann::json empty = nlohmann::json::object();
  if (!v) return ConfigReader(empty, where_, name(key));
  if (!v->is_object()) fail(key, "expected a JSON object, got " + describe(*v));
  return ConfigReader(*v, where_, name(key));
}

void ConfigReader::finish() const {
  for (auto it = object_.begin(); it != object_.end(); ++it) {
    if (!seen_.count(it.key())) {
      std::string known;
      for (const auto& k : seen_) known += (known.empty() ? "" : ", ") + k;
      const std::vector<std::string> names(seen_.begin(), seen_.end());
      fail(one_line(it.key(), 60),
           "unknown key" + did_you_mean(it.key(), names) + " (known keys here: " + known + ")");
    }
  }
}

}  // namespace rdsim
