#include "rdsim/core/json_text.hpp"

#include <nlohmann/json.hpp>
#include <unordered_set>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"

namespace rdsim {
namespace {

// Line and column (1-based) of byte `at`.
std::string position(std::string_view text, std::size_t at) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < at && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Throws when arrays/objects nest deeper than max_json_depth, scanning the text (strings
// skipped) without building anything.
void check_depth(std::string_view text, const std::string& where) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_json_depth)
        throw Error(where + ": not valid for rdsim: arrays/objects nested more than " + std::to_string(max_json_depth) +
                    " levels deep (at " + position(text, i) + ")");
    } else if (c == ']' || c == '}') {
      --depth;  // unbalanced text is the parser's to report
    }
  }
}

// What the parser callback reports a repeated key with.
struct DuplicateKey {
  std::string path;
};

// nlohmann's message without its "[json.exception...]" prefix, on one short line.
std::string nlohmann_reason(const nlohmann::json::exception& e) {
  std::string what = e.what();
  const auto close = what.find("] ");
  if (what.rfind("[json.exception", 0) == 0 && close != std::string::npos) what = what.substr(close + 2);
  return one_line(what, 200);
}

}  // namespace

nlohmann::json parse_json(std::string_view text, const std::string& where, std::uint64_t max_bytes) {
  if (text.size() > max_bytes)
    throw Error(where + ": is " + std::to_string(text.size()) + " bytes, more than the " + std::to_string(max_bytes) +
                " bytes rdsim reads");
  check_depth(text, where);

  // One frame per open array/object; objects remember their keys to catch repeats.
  struct Frame {
    bool object = false;
    std::unordered_set<std::string> keys;
    std::string key;  // the object's current key
  };
  std::vector<Frame> frames;
  const nlohmann::json::parser_callback_t on_event = [&](int, nlohmann::json::parse_event_t event,
                                                          nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    switch (event) {
      case E::object_start: frames.push_back({true, {}, {}}); break;
      case E::array_start: frames.push_back({false, {}, {}}); break;
      case E::object_end:
      case E::array_end:
        if (!frames.empty()) frames.pop_back();
        break;
      case E::key: {
        Frame& f = frames.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second) {
          std::string path;
          for (const Frame& g : frames) {
            if (!g.object) continue;
            path += (path.empty() ? "" : ".") + g.key;
          }
          throw DuplicateKey{path};
        }
        break;
      }
      case E::value: break;
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text.begin(), text.end(), on_event);
  } catch (const DuplicateKey& d) {
    throw Error(where + ": " + one_line(d.path, 200) + ": duplicate key (a key may appear only once in an object)");
  } catch (const nlohmann::json::out_of_range& e) {
    throw Error(where + ": not valid for rdsim: " + nlohmann_reason(e) + " (numbers must fit a double)");
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": not valid JSON: " + nlohmann_reason(e));
  }
}

nlohmann::json read_json_file(const std::string& path) { return parse_json(read_file(path, max_config_bytes), path); }

std::string dump_json(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string json_excerpt(const nlohmann::json& value, std::size_t max_chars) {
  std::string out;
  // Scalars are written whole except long strings, which are cut first (their dump would be long;
  // a cut inside a character is written as U+FFFD by dump_json).
  const auto scalar = [&](const nlohmann::json& v) {
    if (v.is_string() && v.get_ref<const std::string&>().size() > max_chars)
      out += dump_json(nlohmann::json(v.get_ref<const std::string&>().substr(0, max_chars)));
    else
      out += dump_json(v);
  };
  struct Frame {
    const nlohmann::json* v;
    nlohmann::json::const_iterator it;
    bool first = true;
  };
  std::vector<Frame> stack;
  const auto open = [&](const nlohmann::json& v) {
    if (!v.is_structured()) {
      scalar(v);
      return;
    }
    out += v.is_object() ? '{' : '[';
    stack.push_back({&v, v.cbegin()});
  };
  open(value);
  while (!stack.empty() && out.size() <= max_chars) {
    Frame& f = stack.back();
    if (f.it == f.v->cend()) {
      out += f.v->is_object() ? '}' : ']';
      stack.pop_back();
      continue;
    }
    if (!f.first) out += ',';
    f.first = false;
    if (f.v->is_object()) {
      const std::string& key = f.it.key();
      out += dump_json(nlohmann::json(key.size() > max_chars ? key.substr(0, max_chars) : key)) + ':';
    }
    const nlohmann::json& child = *f.it;
    ++f.it;
    open(child);  // may grow the stack: `f` is not used after this
  }
  if (out.size() > max_chars) out = out.substr(0, max_chars > 3 ? max_chars - 3 : 0) + "...";
  return one_line(out, max_chars + 3);
}

}  // namespace rdsim
