// The process-wide cache of loaded meshes and hulls (rdsim/sim/mesh_file.hpp).
#include <cstdio>
#include <filesystem>
#include <future>
#include <map>
#include <mutex>
#include <string>

#include "rdsim/sim/mesh_file.hpp"

namespace rdsim {
namespace {

// What identifies one loaded mesh: the file (canonical path, size and modification time, so an
// edited file is read again) and the scale.
std::string cache_key(const std::string& file, const Eigen::Vector3d& scale) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(file, ec);
  if (ec) canonical = file;
  const std::uintmax_t bytes = fs::file_size(canonical, ec);
  const auto modified = fs::last_write_time(canonical, ec).time_since_epoch().count();
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, "|%ju|%lld|%.17g|%.17g|%.17g", ec ? 0 : bytes, static_cast<long long>(ec ? 0 : modified),
                scale.x(), scale.y(), scale.z());
  return canonical.string() + numbers;
}

// One map of futures per kind of value: the first thread to ask computes outside the lock, the
// others wait on its future; a failure is handed to every waiter, then forgotten.
template <class T>
class Cache {
public:
  template <class Make>
  std::shared_ptr<const T> get(const std::string& key, Make&& make) {
    std::promise<std::shared_ptr<const T>> promise;
    std::shared_future<std::shared_ptr<const T>> future;
    bool owner = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto [it, fresh] = entries_.try_emplace(key);
      if (fresh) it->second = promise.get_future().share();
      future = it->second;
      owner = fresh;
    }
    if (owner) {
      try {
        promise.set_value(std::make_shared<const T>(make()));
      } catch (...) {
        promise.set_exception(std::current_exception());
        std::lock_guard<std::mutex> lock(mutex_);
        entries_.erase(key);
      }
    }
    return future.get();
  }

private:
  std::mutex mutex_;
  std::map<std::string, std::shared_future<std::shared_ptr<const T>>> entries_;
};

Cache<TriangleMesh>& mesh_cache() {
  static Cache<TriangleMesh> cache;
  return cache;
}

Cache<ConvexHull>& hull_cache() {
  static Cache<ConvexHull> cache;
  return cache;
}

}  // namespace

std::shared_ptr<const TriangleMesh> load_mesh(const std::string& file, const Eigen::Vector3d& scale) {
  return mesh_cache().get(cache_key(file, scale), [&] { return read_mesh_file(file, scale); });
}

std::shared_ptr<const ConvexHull> load_convex_hull(const std::string& file, const Eigen::Vector3d& scale) {
  return hull_cache().get(cache_key(file, scale), [&] { return convex_hull(*load_mesh(file, scale)); });
}

}  // namespace rdsim
