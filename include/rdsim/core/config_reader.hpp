#pragma once
#include <nlohmann/json_fwd.hpp>
#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace rdsim {

// Lists in a config (hidden_sizes, channels, ...) hold at most this many entries.
inline constexpr std::size_t max_list_items = 256;
// Strings (names, paths) hold at most this many bytes (PATH_MAX).
inline constexpr std::size_t max_string_bytes = 4096;

// A value typed on the command line as JSON: a number when it reads as one ("-1", "1e18"), else
// the text as a string, so that ConfigReader's checks and messages apply to it as to a file's.
nlohmann::json json_from_option(const std::string& text);

// Reads one JSON object into typed fields, once. Every problem becomes an rdsim::Error naming
// the file and the key path ("configs/x.json: ppo.clip: expected a number in [0, 1], got 3").
// Absent keys leave the field at its default; finish() rejects keys nobody asked for.
class ConfigReader {
public:
  // `where` is the file name; `path` the dotted key prefix ("" at the top level).
  ConfigReader(const nlohmann::json& object, std::string where, std::string path = "");

  bool has(const std::string& key) const;
  // The keys present in this object.
  std::vector<std::string> keys() const;
  void read(const std::string& key, bool& out);
  void read(const std::string& key, std::string& out);
  void read(const std::string& key, int& out, int lo, int hi);
  void read(const std::string& key, long long& out, long long lo, long long hi);
  void read(const std::string& key, std::uint64_t& out);
  void read(const std::string& key, double& out, double lo, double hi);
  void read(const std::string& key, std::vector<int>& out, int lo, int hi);
  void read(const std::string& key, std::vector<double>& out, double lo, double hi);
  // A list of strings (names, paths), each checked as read(key, std::string&) checks one.
  void read(const std::string& key, std::vector<std::string>& out);
  // An object of names with a number each ({"effector_position": 0.005}), at most max_list_items.
  void read(const std::string& key, std::map<std::string, double>& out, double lo, double hi);
  void read_choice(const std::string& key, std::string& out, const std::vector<std::string>& choices);

  // A nested object; its own finish() checks its keys.
  ConfigReader child(const std::string& key);
  // Marks a key as known without reading it (read elsewhere, e.g. by a child reader).
  void accept(const std::string& key);

  // Throws on the first key that no read()/child()/accept() asked for.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  std::string name(const std::string& key) const;
  const std::string& where() const { return where_; }

private:
  const nlohmann::json* find(const std::string& key);

  const nlohmann::json& object_;
  std::string where_;
  std::string path_;
  std::set<std::string> seen_;
};

}  // namespace rdsim
