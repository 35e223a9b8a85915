#pragma once
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/env.hpp"
#include "rdsim/core/env_config.hpp"
#include "rdsim/core/memory_estimate.hpp"

namespace rdsim {

struct EnvEntry {
  std::string name;
  std::string description;
  bool supports_pixels = false;  // has cameras: reads the drawing keys too (describe_env_drawing)
  // Every option with the value the env uses by default: core's keys and the env's own option
  // groups (EnvConfig::options), which say what else it reads.
  EnvConfig (*defaults)();
  std::unique_ptr<Env> (*make)(const EnvConfig&);
};

// Every environment rdsim knows, listed explicitly in envs/registry.cpp (no static-init magic,
// so nothing silently disappears at link time).
const std::vector<EnvEntry>& env_registry();

// The registry entry of `name`; rdsim::Error listing the known names otherwise.
const EnvEntry& env_entry(const std::string& name);

// The env's published defaults (EnvConfig with real values, name set).
EnvConfig default_env_config(const std::string& name);

// The "env" keys `entry` reads with their docs and its default values, "name" first, each from its
// one declaration: core's describe_env_basics, describe_env_drawing (envs with cameras), then the
// describe() of each option group its defaults hold.
std::vector<config::FieldDoc> env_fields(const EnvEntry& entry);
// The keys of env_fields(entry), in that order, as the env object holds them: an object key
// ("randomize") once for all its fields ("randomize.action_latency", ...).
std::vector<std::string> env_keys(const EnvEntry& entry);
bool env_reads(const EnvEntry& entry, const std::string& key);

// Makes the relative file paths among `config`'s options (reach's urdf and package_paths) absolute
// paths relative to `folder`: a config file's paths are relative to the file's folder. Options given
// in code or from Python stay as they are (relative to the current directory).
void resolve_env_paths(EnvConfig& config, const std::string& folder);

// Reads the "env" object of a config: "name" first, then the other keys over that env's
// defaults, so the result holds the values the env will use. Unknown keys, keys the env does not
// read, wrong types and out-of-range values are rdsim::Errors naming the key.
EnvConfig read_env_config(ConfigReader& reader);

// The resolved "env" object: name and every key the env reads, with its value.
nlohmann::json to_json(const EnvConfig& config);

// The Spec envs of `config` have, without building a renderer: a ground-truth twin of the env is
// built once to ask it (cheap), and a raw-pixel space comes from the config (pixel_space). So
// nothing large is allocated before the memory estimate is checked.
Spec env_spec(const EnvConfig& config);

// Adds what `num_envs` envs of `config` will allocate to `estimate`: physics worlds and, when they
// draw, framebuffers and images (from the config; nothing is built).
void estimate_env_memory(const EnvConfig& config, int num_envs, MemoryEstimate& estimate);

// Creates the env named by config.name after checking every value against the same rules as
// read_env_config (so a config built in code meets them too).
std::unique_ptr<Env> make_env(const EnvConfig& config);

}  // namespace rdsim
