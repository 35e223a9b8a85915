#include "web_assets.hpp"

namespace rdsim::web {

const Asset* find_asset(std::string_view path) {
  for (std::size_t i = 0; i < asset_count; ++i) {
    if (path == assets[i].path) return &assets[i];
  }
  return nullptr;
}

const char* content_type(std::string_view path) {
  if (path.ends_with(".html")) return "text/html; charset=utf-8";
  if (path.ends_with(".js")) return "text/javascript; charset=utf-8";
  if (path.ends_with(".css")) return "text/css; charset=utf-8";
  if (path.ends_with(".png")) return "image/png";
  return "text/plain; charset=utf-8";
}

}  // namespace rdsim::web
