#include "rdsim/dashboard/run_index.hpp"

#include <algorithm>
#include <cerrno>
#include <filesystem>

#include "rdsim/core/csv_reader.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {

namespace fs = std::filesystem;

namespace {

// Whether `path` equals `root` or lies below it, compared component by component (so /runs2 is
// not inside /runs).
bool is_within(const fs::path& path, const fs::path& root) {
  auto p = path.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++p) {
    if (r->empty()) continue;  // a trailing separator
    if (p == path.end() || *p != *r) return false;
  }
  return true;
}

}  // namespace

RunIndex::RunIndex(std::vector<std::string> roots) : roots_(std::move(roots)) {
  for (const auto& root : roots_) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) throw Error(root + ": not a folder (give the folder that holds the run folders)");
    canonical_roots_.push_back(fs::canonical(root, ec).string());
    if (ec) throw Error(root + ": " + ec.message());
  }
}

bool RunIndex::inside_root(const std::string& file, std::size_t root_number) const {
  if (root_number >= canonical_roots_.size()) return false;
  std::error_code ec;
  const fs::path real = fs::canonical(file, ec);
  return !ec && is_within(real, canonical_roots_[root_number]);
}

std::optional<InputFile> RunIndex::open_log(const IndexedRun& run, const char* name) const {
  try {
    return InputFile::beneath(roots_[run.root], run.below + "/" + name, max_csv_log_bytes);
  } catch (const FileOpenError& e) {
    if (e.code() == ENOENT) return std::nullopt;
    if (e.link_out() || e.code() == ENOTDIR) throw RunOutsideRoot(e.what());
    throw;
  }
}

void RunIndex::rescan(bool force) {
  const auto now = std::chrono::steady_clock::now();
  // Scanning walks the folders: bounded in rate whatever the requests ask for.
  const auto min_age = force ? std::chrono::milliseconds(200) : std::chrono::milliseconds(1000);
  if (scanned_once_ && now - scanned_ < min_age) return;
  std::vector<IndexedRun> found;
  for (std::size_t k = 0; k < roots_.size(); ++k) {
    std::vector<std::string> dirs;
    try {
      dirs = find_run_folders(roots_[k]);
    } catch (const Error&) {
      continue;  // the root went away: it serves nothing until it is back
    }
    for (const auto& dir : dirs) {
      IndexedRun run;
      const std::string below = fs::path(dir).lexically_relative(roots_[k]).generic_string();
      run.id = std::to_string(k) + ":" + below;
      // Short names: the path below the root (the root's own name for a root that is a run), under
      // the root's name when there are several roots.
      const std::string root_name = fs::path(canonical_roots_[k]).filename().string();
      run.label = below == "." ? root_name : roots_.size() > 1 ? root_name + "/" + below : below;
      run.info = read_run_info_beneath(roots_[k], below);
      run.info.dir = dir;
      run.progress_path = (fs::path(dir) / progress_csv_name).string();
      run.root = k;
      run.below = below;
      // A run folder, or a progress.csv, reached through a link that leaves the root is not served.
      std::error_code ec;
      const bool has_log = fs::exists(run.progress_path, ec) || fs::is_symlink(run.progress_path, ec);
      if (inside_root(dir, k) && (!has_log || inside_root(run.progress_path, k))) found.push_back(std::move(run));
    }
  }
  runs_ = std::move(found);
  scanned_ = now;
  scanned_once_ = true;
}

std::vector<IndexedRun> RunIndex::runs() {
  std::lock_guard lock(mutex_);
  rescan(false);
  return runs_;
}

std::optional<IndexedRun> RunIndex::find(const std::string& id) {
  std::lock_guard lock(mutex_);
  if (!scanned_once_) rescan(true);
  auto it = std::find_if(runs_.begin(), runs_.end(), [&](const IndexedRun& r) { return r.id == id; });
  if (it == runs_.end()) {
    rescan(true);
    it = std::find_if(runs_.begin(), runs_.end(), [&](const IndexedRun& r) { return r.id == id; });
  }
  if (it == runs_.end()) return std::nullopt;
  return *it;
}

}  // namespace rdsim
