#pragma once
#include <cstddef>
#include <string_view>

// The dashboard's page: the files of src/dashboard/web/, embedded into the binary at build time
// (embed_web_assets.cmake writes web_assets_data.cpp), so `rdsim` needs no file beside it.
namespace rdsim::web {

struct Asset {
  const char* path;            // relative to src/dashboard/web/: "index.html", "vendor/uplot-1.6.32/uPlot.min.css"
  const unsigned char* bytes;
  std::size_t size;
};

extern const Asset assets[];
extern const std::size_t asset_count;

// The embedded file at exactly `path`, or nullptr. Never touches the file system.
const Asset* find_asset(std::string_view path);

// Content-Type for a file name by its extension.
const char* content_type(std::string_view path);

}  // namespace rdsim::web
