// What a DAE file must satisfy before Assimp reads it (dae_check.hpp).
#include "dae_check.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <map>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/sim/mesh_file.hpp"

namespace rdsim {
namespace {

// A count larger than 16 values per triangle corner of the largest mesh rdsim loads is no mesh's.
constexpr std::uint64_t kMaxDaeCount = 16ull * max_mesh_triangles * 3;

struct Tag {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  // as written (entities undecoded)
  std::size_t end = 0;                                          // one past its '>'
  bool closing = false;                                         // </name>
  bool self_closing = false;                                    // <name .../>
};

bool name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' || c == '.'; }
bool space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// The tag starting at xml[at] == '<', read the way an XML parser reads it: a '>' inside a quoted
// attribute value does not end it. None when the document ends first (the XML parser reports that).
std::optional<Tag> read_tag(std::string_view xml, std::size_t at) {
  Tag tag;
  std::size_t i = at + 1;
  if (i < xml.size() && xml[i] == '/') {
    tag.closing = true;
    ++i;
  }
  const std::size_t name_begin = i;
  while (i < xml.size() && name_char(xml[i])) ++i;
  tag.name = std::string(xml.substr(name_begin, i - name_begin));
  while (i < xml.size()) {
    while (i < xml.size() && space(xml[i])) ++i;
    if (i >= xml.size()) break;
    if (xml[i] == '>') {
      tag.end = i + 1;
      return tag;
    }
    if (xml[i] == '/' && i + 1 < xml.size() && xml[i + 1] == '>') {
      tag.self_closing = true;
      tag.end = i + 2;
      return tag;
    }
    const std::size_t key_begin = i;
    while (i < xml.size() && name_char(xml[i])) ++i;
    std::string key(xml.substr(key_begin, i - key_begin));
    while (i < xml.size() && space(xml[i])) ++i;
    if (key.empty() || i >= xml.size() || xml[i] != '=') {  // not XML: skip a byte, as the parser will fail
      ++i;
      continue;
    }
    ++i;
    while (i < xml.size() && space(xml[i])) ++i;
    if (i >= xml.size() || (xml[i] != '"' && xml[i] != '\'')) continue;
    const std::size_t close = xml.find(xml[i], i + 1);
    if (close == std::string_view::npos) return std::nullopt;
    tag.attributes.emplace_back(std::move(key), std::string(xml.substr(i + 1, close - i - 1)));
    i = close + 1;
  }
  return std::nullopt;
}

struct Accessor {
  std::string source;
  std::uint64_t count = 0, stride = 1, offset = 0;
  std::uint64_t values = 0;  // per element, from its params (a float4x4 param is 16)
};

class DaeChecker {
 public:
  DaeChecker(std::string_view xml, const std::string& file) : xml_(xml), file_(file) {}

  void run() {
    std::size_t at = xml_.find('<');
    while (at != std::string_view::npos) {
      const std::size_t next = skip_markup(at);
      if (next != at) {
        at = next == std::string_view::npos ? next : xml_.find('<', next);
        continue;
      }
      const std::optional<Tag> tag = read_tag(xml_, at);
      if (!tag) break;
      visit(*tag);
      at = xml_.find('<', tag->end);
    }
    for (const Accessor& a : accessors_) check_reads(a);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw Error(file_ + ": not a readable DAE file: " + why); }

  // Past a comment, CDATA section, processing instruction or declaration at `at`; `at` itself when
  // a tag starts there; npos when it never ends.
  std::size_t skip_markup(std::size_t at) const {
    const auto past = [&](std::string_view end) {
      const std::size_t e = xml_.find(end, at);
      return e == std::string_view::npos ? e : e + end.size();
    };
    const std::string_view rest = xml_.substr(at);
    if (rest.substr(0, 4) == "<!--") return past("-->");
    if (rest.substr(0, 9) == "<![CDATA[") return past("]]>");
    if (rest.substr(0, 2) == "<?") return past("?>");
    if (rest.substr(0, 2) == "<!") return past(">");
    return at;
  }

  std::optional<std::string> attribute(const Tag& tag, std::string_view key) const {
    std::optional<std::string> found;
    for (const auto& [k, v] : tag.attributes)
      if (k == key) {
        if (found) fail("<" + tag.name + "> has two " + std::string(key) + " attributes");
        found = v;
      }
    return found;
  }

  // A size attribute: plain digits, at most kMaxDaeCount (an XML parser also reads "0x10", " 7"
  // or "&#55;", whose value this check would have to guess).
  std::optional<std::uint64_t> size_attribute(const Tag& tag, std::string_view key) const {
    const std::optional<std::string> text = attribute(tag, key);
    if (!text) return std::nullopt;
    const std::string where = "<" + tag.name + "> " + std::string(key) + " ";
    if (text->empty() || text->size() > 19 ||
        !std::all_of(text->begin(), text->end(), [](unsigned char c) { return std::isdigit(c); }))
      fail(where + "\"" + one_line(*text, 40) + "\" is not a whole number");
    const std::uint64_t n = std::stoull(*text);
    if (n > kMaxDaeCount) fail(where + "over " + std::to_string(kMaxDaeCount));
    return n;
  }

  void visit(const Tag& tag) {
    if (tag.closing) {
      if (tag.name == "accessor") in_accessor_ = false;
      return;
    }
    const std::optional<std::uint64_t> count = size_attribute(tag, "count");
    const bool is_array = tag.name.size() > 6 && tag.name.compare(tag.name.size() - 6, 6, "_array") == 0;
    if (is_array) {
      if (const std::optional<std::string> id = attribute(tag, "id"))
        if (!arrays_.emplace(*id, count.value_or(0)).second) fail("two arrays have the id \"" + one_line(*id, 40) + "\"");
    }
    if (tag.name == "accessor") {
      Accessor a;
      a.source = attribute(tag, "source").value_or("");
      a.count = count.value_or(0);
      a.stride = size_attribute(tag, "stride").value_or(1);
      a.offset = size_attribute(tag, "offset").value_or(0);
      accessors_.push_back(std::move(a));
      in_accessor_ = !tag.self_closing;
    } else if (tag.name == "param" && in_accessor_) {
      accessors_.back().values += attribute(tag, "type").value_or("") == "float4x4" ? 16 : 1;
    }
    if (!tag.self_closing) check_list_text(tag);
  }

  // The text of a number list holds only what numbers are made of, and no markup.
  void check_list_text(const Tag& tag) const {
    const bool integers = tag.name == "p" || tag.name == "v" || tag.name == "vcount" || tag.name == "h";
    if (!integers && tag.name != "float_array") return;
    const std::size_t text_end = xml_.find('<', tag.end);
    if (text_end == std::string_view::npos) return;  // unterminated: the XML parser reports it
    if (xml_.substr(text_end, 2) != "</") fail("<" + tag.name + "> holds markup where numbers are expected");
    const char* allowed = integers ? "0123456789+- \t\r\n" : "0123456789+-.eEnNaAiIfF \t\r\n";
    const std::size_t bad = xml_.find_first_not_of(allowed, tag.end);
    if (bad < text_end)
      fail("<" + tag.name + "> holds " + one_line(std::string(1, xml_[bad])) + " where " + (integers ? "integers" : "numbers") +
           " are expected");
  }

  // Assimp reads element i of an accessor at offset + i * stride + k, k below its values per element.
  void check_reads(const Accessor& a) const {
    if (a.source.size() < 2 || a.source[0] != '#') fail("an <accessor> source \"" + one_line(a.source, 40) + "\" is not \"#<array id>\"");
    const auto array = arrays_.find(a.source.substr(1));
    if (array == arrays_.end()) fail("an <accessor> names \"" + one_line(a.source, 40) + "\", which is no array of the file");
    if (a.count == 0) return;
    const std::uint64_t width = std::max<std::uint64_t>({1, a.stride, a.values});
    const std::uint64_t needed = a.offset + a.count * width;  // each term at most kMaxDaeCount: no overflow
    if (needed > array->second)
      fail("an <accessor> reads " + std::to_string(needed) + " values of \"" + one_line(a.source, 40) + "\", which holds " +
           std::to_string(array->second));
  }

  std::string_view xml_;
  const std::string& file_;
  std::map<std::string, std::uint64_t> arrays_;  // id -> values it holds (its count; none without one)
  std::vector<Accessor> accessors_;
  bool in_accessor_ = false;
};

}  // namespace

void check_dae_file(const std::string& xml, const std::string& file) { DaeChecker(xml, file).run(); }

}  // namespace rdsim
