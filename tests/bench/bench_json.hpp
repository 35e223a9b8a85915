#pragma once
// A benchmark command run from a test: its results JSON, written to a scratch file and read back.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "rdsim/core/files.hpp"

namespace rdsim::test {

// `options` with json_path set to a file named after `name` in the temp folder (removed once read); REQUIREs exit 0.
template <class Options>
nlohmann::json bench_json(Options options, int (*command)(const Options&), const std::string& name) {
  const std::filesystem::path json = std::filesystem::temp_directory_path() / ("rdsim_test_" + name + ".json");
  options.json_path = json.string();
  REQUIRE(command(options) == 0);
  nlohmann::json result = nlohmann::json::parse(read_file(json.string()));
  std::filesystem::remove(json);
  return result;
}

}  // namespace rdsim::test
