#include "rdsim/core/config_reader.hpp"

#include <climits>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

std::string describe(const nlohmann::json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

template <class T>
std::string range_text(T lo, T hi) {
  std::ostringstream os;
  os << "in [" << lo << ", " << hi << "]";
  return os.str();
}

}  // namespace

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

void ConfigReader::read(const std::string& key, std::string& out) {
  const auto* v = find(key);
  if (!v) return;
  if (!v->is_string()) fail(key, "expected a string, got " + describe(*v));
  out = v->get<std::string>();
}

void ConfigReader::read(const std::string& key, long long& out, long long lo, long long hi) {
  const auto* v = find(key);
  if (!v) return;
  bool integral = v->is_number_integer();
  if (v->is_number_float()) {
    // Casting a double outside long long's range is undefined behaviour: such a number is not
    // an integer we can hold (and no range here reaches 9.2e18).
    const double d = v->get<double>();
    integral = d >= -9.2e18 && d <= 9.2e18 && d == std::trunc(d);
  }
  // An unsigned value above long long's range would wrap to a negative number.
  if (v->is_number_unsigned() && v->get<std::uint64_t>() > static_cast<std::uint64_t>(LLONG_MAX)) integral = false;
  if (!integral) fail(key, "expected an integer " + range_text(lo, hi) + ", got " + describe(*v));
  long long x = v->is_number_float() ? static_cast<long long>(v->get<double>()) : v->get<long long>();
  if (x < lo || x > hi) fail(key, "expected an integer " + range_text(lo, hi) + ", got " + describe(*v));
  out = x;
}

void ConfigReader::read(const std::string& key, int& out, int lo, int hi) {
  long long x = out;
  read(key, x, lo, hi);
  out = static_cast<int>(x);
}

void ConfigReader::read(const std::string& key, std::uint64_t& out) {
  const auto* v = find(key);
  if (!v) return;
  if (!v->is_number_unsigned() && !(v->is_number_integer() && v->get<long long>() >= 0)) {
    fail(key, "expected a non-negative integer, got " + describe(*v));
  }
  out = v->get<std::uint64_t>();
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
  if (!v->is_array()) fail(key, "expected a list of integers " + range_text(lo, hi) + ", got " + describe(*v));
  std::vector<int> result;
  for (const auto& e : *v) {
    const bool too_big = e.is_number_unsigned() && e.get<std::uint64_t>() > static_cast<std::uint64_t>(LLONG_MAX);
    if (!e.is_number_integer() || too_big || e.get<long long>() < lo || e.get<long long>() > hi) {
      fail(key, "expected a list of integers " + range_text(lo, hi) + ", got " + describe(*v));
    }
    result.push_back(e.get<int>());
  }
  out = std::move(result);
}

void ConfigReader::read(const std::string& key, std::vector<double>& out, double lo, double hi) {
  const auto* v = find(key);
  if (!v) return;
  if (!v->is_array()) fail(key, "expected a list of numbers " + range_text(lo, hi) + ", got " + describe(*v));
  std::vector<double> result;
  for (const auto& e : *v) {
    if (!e.is_number() || !(e.get<double>() >= lo && e.get<double>() <= hi)) {
      fail(key, "expected a list of numbers " + range_text(lo, hi) + ", got " + describe(*v));
    }
    result.push_back(e.get<double>());
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
  fail(key, "expected one of " + list + ", got \"" + value + "\"");
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
      fail(it.key(), "unknown key (known keys here: " + known + ")");
    }
  }
}

}  // namespace rdsim
