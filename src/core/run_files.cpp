#include "rdsim/core/run_files.hpp"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/input_file.hpp"
#include "rdsim/core/json_text.hpp"

namespace rdsim {

namespace fs = std::filesystem;

namespace {

RunInfo parse_run_info(const std::string& dir, const std::string& text) {
  RunInfo info;
  info.dir = dir;
  const nlohmann::json config = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!config.is_object()) return info;
  if (auto a = config.find("algorithm"); a != config.end() && a->is_string()) info.algorithm = *a;
  if (auto e = config.find("env"); e != config.end() && e->is_object()) {
    if (auto n = e->find("name"); n != e->end() && n->is_string()) info.env = *n;
  }
  if (auto s = config.find("seed"); s != config.end() && s->is_number_unsigned()) info.seed = s->get<std::uint64_t>();
  return info;
}

}  // namespace

RunInfo read_run_info(const std::string& dir) {
  std::string text;
  try {
    text = read_file((fs::path(dir) / run_config_name).string(), max_config_bytes);  // a regular file only
  } catch (const Error&) {
  }
  return parse_run_info(dir, text);
}

RunInfo read_run_info_beneath(const std::string& root, const std::string& below) {
  std::string text;
  try {
    text = InputFile::beneath(root, below + "/" + run_config_name, max_config_bytes).read_rest();
  } catch (const Error&) {
  }
  return parse_run_info((fs::path(root) / below).lexically_normal().string(), text);
}

std::vector<std::string> find_run_folders(const std::string& root, int max_depth, std::size_t max_runs) {
  std::error_code ec;
  if (!fs::is_directory(root, ec)) throw Error(root + ": not a folder");
  std::vector<std::string> runs;
  auto is_run = [](const fs::path& dir) {
    std::error_code e;
    return fs::is_regular_file(dir / progress_csv_name, e) || fs::is_regular_file(dir / run_config_name, e);
  };
  if (is_run(root)) runs.push_back(root);
  fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
  for (; !ec && it != end && runs.size() < max_runs; it.increment(ec)) {
    std::error_code e;
    if (!it->is_directory(e) || it->is_symlink(e)) {
      continue;
    }
    if (it.depth() + 1 >= max_depth) it.disable_recursion_pending();
    if (is_run(it->path())) runs.push_back(it->path().string());
  }
  std::sort(runs.begin(), runs.end());
  return runs;
}

}  // namespace rdsim
