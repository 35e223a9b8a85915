#include "rdsim/demos/demo_file.hpp"

#include <cmath>
#include <cstring>
#include <sstream>

#include "demo_layout.hpp"
#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/checksum.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"
#include "rdsim/demos/demo_fit.hpp"

namespace rdsim {
namespace {

using nlohmann::json;

constexpr std::uint8_t kSuccess = 1, kCollision = 2, kOutOfBounds = 4;
constexpr std::uint64_t kMaxObservationSize = 1ull << 28;  // values per observation (a 4096x4096x6 image fits)

std::string u64_bytes(std::uint64_t v) {
  std::ostringstream out;
  write_u64(out, v);
  return out.str();
}

bool all_finite(const Eigen::VectorXf& v) { return v.allFinite(); }

std::vector<float> to_vector(const Eigen::VectorXf& v) { return {v.data(), v.data() + v.size()}; }

Eigen::VectorXf from_json_floats(const json& j, const std::string& where, const char* key) {
  if (!j.contains(key) || !j[key].is_array()) throw Error(where + ": spec." + key + ": expected a list of numbers");
  Eigen::VectorXf v(static_cast<Eigen::Index>(j[key].size()));
  for (std::size_t i = 0; i < j[key].size(); ++i) {
    if (!j[key][i].is_number()) throw Error(where + ": spec." + key + ": expected a list of numbers");
    v[static_cast<Eigen::Index>(i)] = j[key][i].get<float>();
  }
  return v;
}

// Reads what every record and the header share: a checked length, then that many bytes.
class Reader {
public:
  Reader(std::string_view bytes, std::size_t pos, std::size_t end, const std::string& source)
      : bytes_(bytes), pos_(pos), end_(end), source_(source) {}

  std::size_t pos() const { return pos_; }
  std::size_t left() const { return end_ - pos_; }
  template <class T>
  T get(const char* what) {
    T v;
    std::memcpy(&v, take(sizeof(T), what).data(), sizeof(T));
    return v;
  }
  std::string_view take(std::size_t n, const char* what) {
    if (n > left()) throw Error(source_ + ": file is damaged (" + what + " runs past the committed data)");
    std::string_view s = bytes_.substr(pos_, n);
    pos_ += n;
    return s;
  }

private:
  std::string_view bytes_;
  std::size_t pos_, end_;
  const std::string& source_;
};

std::uint64_t observation_bytes(const Spec& spec) {
  return static_cast<std::uint64_t>(spec.observation.size()) * (spec.observation.type == ObsType::UInt8 ? 1u : 4u);
}
std::uint64_t action_bytes(const Spec& spec) { return 4u * static_cast<std::uint64_t>(spec.action.dim()); }
// Bytes of the arrays of an episode of `steps` steps.
std::uint64_t array_bytes(const Spec& spec, std::uint64_t steps) {
  return (steps + 1) * observation_bytes(spec) + steps * (action_bytes(spec) + 4 + 4 + 1);
}

json episode_meta(const DemoEpisode& e) {
  json meta = json::object();
  meta["source"] = to_string(e.source);
  meta["seed"] = e.seed ? json(*e.seed) : json(nullptr);
  meta["env"] = e.env_config;
  meta["steps"] = e.steps();
  meta["terminated"] = e.terminated;
  meta["truncated"] = e.truncated;
  meta["return"] = e.episode_return();
  meta["success"] = e.success();
  return meta;
}

DemoEpisode decode_episode(std::string_view body, const DemoFile& file, const std::string& where) {
  Reader r(body, 0, body.size(), where);
  const auto meta_size = r.get<std::uint64_t>("the episode's JSON length");
  const std::string_view meta_text = r.take(meta_size, "the episode's JSON");
  json meta;
  try {
    meta = json::parse(meta_text);
  } catch (const json::exception&) {
    throw Error(where + ": its JSON is not valid");
  }
  if (!meta.is_object()) throw Error(where + ": its JSON is not an object");
  auto field = [&](const char* key, bool ok) -> const json& {
    if (!meta.contains(key) || !ok) throw Error(where + ": \"" + key + "\" is missing or has the wrong type");
    return meta[key];
  };
  DemoEpisode e;
  const json& source = field("source", meta.contains("source") && meta["source"].is_string());
  if (source == "scripted")
    e.source = DemoSource::Scripted;
  else if (source == "human")
    e.source = DemoSource::Human;
  else
    throw Error(where + ": \"source\" must be \"scripted\" or \"human\"");
  const json& seed = field("seed", meta.contains("seed") && (meta["seed"].is_null() || meta["seed"].is_number_unsigned()));
  if (!seed.is_null()) e.seed = seed.get<std::uint64_t>();
  e.env_config = field("env", meta.contains("env") && meta["env"].is_object());
  const auto steps = field("steps", meta.contains("steps") && meta["steps"].is_number_unsigned()).get<std::uint64_t>();
  e.terminated = field("terminated", meta.contains("terminated") && meta["terminated"].is_boolean()).get<bool>();
  e.truncated = field("truncated", meta.contains("truncated") && meta["truncated"].is_boolean()).get<bool>();
  const double recorded_return = field("return", meta.contains("return") && meta["return"].is_number()).get<double>();
  const bool recorded_success = field("success", meta.contains("success") && meta["success"].is_boolean()).get<bool>();

  if (steps > r.left() || array_bytes(file.spec, steps) != r.left())
    throw Error(where + ": its data does not hold " + std::to_string(steps) + " steps of this env's observations and actions");
  const int n = static_cast<int>(steps);
  const Spec& spec = file.spec;
  const int obs_size = spec.observation.size();
  e.observations.resize(static_cast<std::size_t>(n) + 1);
  for (Observation& o : e.observations) {
    if (spec.observation.type == ObsType::UInt8) {
      const std::string_view b = r.take(static_cast<std::size_t>(obs_size), "an observation");
      o.pixels.assign(b.begin(), b.end());
    } else {
      o.values.resize(obs_size);
      std::memcpy(o.values.data(), r.take(4u * static_cast<std::size_t>(obs_size), "an observation").data(),
                  4u * static_cast<std::size_t>(obs_size));
    }
  }
  e.actions.resize(static_cast<std::size_t>(n));
  for (Action& a : e.actions) {
    if (spec.action.discrete) {
      a.index = r.get<std::int32_t>("an action");
    } else {
      a.values.resize(spec.action.dim());
      for (int k = 0; k < spec.action.dim(); ++k) a.values[k] = r.get<float>("an action");
    }
  }
  e.rewards.resize(static_cast<std::size_t>(n));
  for (float& v : e.rewards) v = r.get<float>("a reward");
  e.infos.resize(static_cast<std::size_t>(n));
  for (StepInfo& info : e.infos) info.distance = r.get<float>("a distance");
  for (StepInfo& info : e.infos) {
    const auto flags = r.get<std::uint8_t>("a step's flags");
    if (flags & ~(kSuccess | kCollision | kOutOfBounds)) throw Error(where + ": a step has unknown flags");
    info.success = flags & kSuccess;
    info.collision = flags & kCollision;
    info.out_of_bounds = flags & kOutOfBounds;
  }
  validate_episode(e, spec, where);
  if (e.success() != recorded_success || std::abs(e.episode_return() - recorded_return) > 1e-6 * (1.0 + std::abs(recorded_return)))
    throw Error(where + ": its recorded return or success does not match its steps");
  const std::string problem = demos_fit_problem(file.env_config, spec, e.env_config, spec);
  if (!problem.empty()) throw Error(where + ": recorded with other env settings than the file's header: " + problem);
  return e;
}

}  // namespace

namespace demo_layout {

std::string commit_record(std::uint64_t committed_length, std::uint64_t episodes) {
  std::ostringstream head;
  head.write(magic, sizeof magic);
  write_u32(head, demo_format_version);
  write_u32(head, 0);
  write_u64(head, committed_length);
  write_u64(head, episodes);
  const std::string first = head.str();
  return first.substr(commit_offset) + u64_bytes(fnv1a64(first));
}

}  // namespace demo_layout

std::string describe_action_space(const ActionSpace& space) {
  return space.discrete ? "Discrete(" + std::to_string(space.n) + ")" : "Box(" + std::to_string(space.dim()) + ")";
}

std::string describe_observation_space(const ObservationSpace& space) {
  std::string text = space.type == ObsType::UInt8 ? "UInt8[" : "Float32[";
  for (std::size_t i = 0; i < space.shape.size(); ++i) {
    if (i > 0) text += 'x';
    text += std::to_string(space.shape[i]);
  }
  text += ']';
  if (space.vector_size > 0) text += " + Float32[" + std::to_string(space.vector_size) + "]";
  return text;
}

json spec_to_json(const Spec& spec) {
  json j = json::object();
  j["env_name"] = spec.env_name;
  j["observation"] = {{"type", spec.observation.type == ObsType::UInt8 ? "uint8" : "float32"},
                      {"shape", spec.observation.shape}};
  if (spec.action.discrete)
    j["action"] = {{"discrete", true}, {"n", spec.action.n}};
  else
    j["action"] = {{"discrete", false}, {"low", to_vector(spec.action.low)}, {"high", to_vector(spec.action.high)}};
  j["max_episode_steps"] = spec.max_episode_steps;
  return j;
}

Spec spec_from_json(const json& j, const std::string& where) {
  auto bad = [&](const std::string& what) { return Error(where + ": spec." + what); };
  if (!j.is_object()) throw bad("expected an object");
  Spec s;
  if (!j.contains("env_name") || !j["env_name"].is_string()) throw bad("env_name: expected a string");
  s.env_name = j["env_name"].get<std::string>();
  if (!j.contains("observation") || !j["observation"].is_object()) throw bad("observation: expected an object");
  const json& o = j["observation"];
  if (!o.contains("type") || !(o["type"] == "uint8" || o["type"] == "float32"))
    throw bad("observation.type: expected \"float32\" or \"uint8\"");
  s.observation.type = o["type"] == "uint8" ? ObsType::UInt8 : ObsType::Float32;
  if (!o.contains("shape") || !o["shape"].is_array() || o["shape"].empty() || o["shape"].size() > 4)
    throw bad("observation.shape: expected 1 to 4 sizes");
  std::uint64_t size = 1;
  for (const json& d : o["shape"]) {
    if (!d.is_number_unsigned() || d.get<std::uint64_t>() < 1 || d.get<std::uint64_t>() > kMaxObservationSize)
      throw bad("observation.shape: expected positive sizes");
    size *= d.get<std::uint64_t>();
    if (size > kMaxObservationSize) throw bad("observation.shape: too large");
    s.observation.shape.push_back(d.get<int>());
  }
  if (!j.contains("action") || !j["action"].is_object()) throw bad("action: expected an object");
  const json& a = j["action"];
  if (!a.contains("discrete") || !a["discrete"].is_boolean()) throw bad("action.discrete: expected true or false");
  s.action.discrete = a["discrete"].get<bool>();
  if (s.action.discrete) {
    if (!a.contains("n") || !a["n"].is_number_unsigned() || a["n"].get<std::uint64_t>() < 1 ||
        a["n"].get<std::uint64_t>() > (1u << 30))
      throw bad("action.n: expected a positive number of actions");
    s.action.n = a["n"].get<int>();
  } else {
    s.action.low = from_json_floats(a, where + ": spec.action", "low");
    s.action.high = from_json_floats(a, where + ": spec.action", "high");
    if (s.action.low.size() < 1 || s.action.low.size() != s.action.high.size() || !all_finite(s.action.low) ||
        !all_finite(s.action.high) || (s.action.low.array() > s.action.high.array()).any())
      throw bad("action: low and high must be finite bounds of the same length, low <= high");
  }
  if (!j.contains("max_episode_steps") || !j["max_episode_steps"].is_number_integer() || j["max_episode_steps"].get<long long>() < 0 ||
      j["max_episode_steps"].get<long long>() > (1ll << 31) - 1)
    throw bad("max_episode_steps: expected a step count");
  s.max_episode_steps = j["max_episode_steps"].get<int>();
  return s;
}

void validate_episode(const DemoEpisode& e, const Spec& spec, const std::string& where) {
  const std::size_t n = e.actions.size();
  if (n == 0) throw Error(where + ": an episode needs at least one step");
  if (e.observations.size() != n + 1 || e.rewards.size() != n || e.infos.size() != n)
    throw Error(where + ": expected " + std::to_string(n + 1) + " observations and " + std::to_string(n) +
                " rewards and step infos for " + std::to_string(n) + " actions");
  if (spec.max_episode_steps > 0 && n > static_cast<std::size_t>(spec.max_episode_steps))
    throw Error(where + ": " + std::to_string(n) + " steps, more than the env's limit of " +
                std::to_string(spec.max_episode_steps));
  const auto obs_size = static_cast<std::size_t>(spec.observation.size());
  for (std::size_t t = 0; t < e.observations.size(); ++t) {
    const Observation& o = e.observations[t];
    const bool ok = spec.observation.type == ObsType::UInt8
                        ? o.pixels.size() == obs_size && o.values.size() == 0
                        : static_cast<std::size_t>(o.values.size()) == obs_size && o.pixels.empty() && all_finite(o.values);
    if (!ok)
      throw Error(where + ": observation " + std::to_string(t) + " is not a finite " +
                  describe_observation_space(spec.observation) + " observation");
  }
  const ActionSpace& as = spec.action;
  for (std::size_t t = 0; t < n; ++t) {
    const Action& a = e.actions[t];
    const bool ok = as.discrete ? a.index >= 0 && a.index < as.n
                                : a.values.size() == as.low.size() && all_finite(a.values) &&
                                      (a.values.array() >= as.low.array()).all() && (a.values.array() <= as.high.array()).all();
    if (!ok) throw Error(where + ": action " + std::to_string(t) + " is outside the action space " + describe_action_space(as));
    if (!std::isfinite(e.rewards[t]) || !std::isfinite(e.infos[t].distance))
      throw Error(where + ": step " + std::to_string(t) + " has a reward or distance that is not finite");
  }
  if (!e.env_config.is_object()) throw Error(where + ": its env config is not an object");
}

std::string encode_demo_file(const json& env_config, const Spec& spec) {
  if (spec.observation.vector_size > 0)
    throw Error("demonstrations: env \"" + spec.env_name + "\" observes camera images with its goals beside them, "
                "which demonstration files do not hold yet: record with env.observation \"ground_truth\"");
  json header = json::object();
  header["format"] = "rdsim demonstrations";
  header["rdsim_version"] = RDSIM_VERSION;
  header["env"] = env_config;
  header["spec"] = spec_to_json(spec);
  const std::string text = header.dump();
  const std::string head = u64_bytes(text.size()) + text;
  const std::uint64_t length = demo_layout::header_offset + head.size() + 8;
  std::ostringstream prefix;
  prefix.write(demo_layout::magic, sizeof demo_layout::magic);
  write_u32(prefix, demo_format_version);
  write_u32(prefix, 0);  // reserved
  std::string out = prefix.str();
  out += demo_layout::commit_record(length, 0);
  out += head;
  out += u64_bytes(fnv1a64(head));
  return out;
}

std::string encode_demo_episode(const DemoEpisode& e, const Spec& spec, const std::string& where) {
  validate_episode(e, spec, where);
  std::ostringstream body;
  write_string(body, episode_meta(e).dump());
  for (const Observation& o : e.observations) {
    if (spec.observation.type == ObsType::UInt8)
      body.write(reinterpret_cast<const char*>(o.pixels.data()), static_cast<std::streamsize>(o.pixels.size()));
    else
      body.write(reinterpret_cast<const char*>(o.values.data()), static_cast<std::streamsize>(4 * o.values.size()));
  }
  for (const Action& a : e.actions) {
    if (spec.action.discrete) {
      write_u32(body, static_cast<std::uint32_t>(a.index));
    } else {
      for (Eigen::Index k = 0; k < a.values.size(); ++k) write_f32(body, a.values[k]);
    }
  }
  for (float r : e.rewards) write_f32(body, r);
  for (const StepInfo& info : e.infos) write_f32(body, info.distance);
  for (const StepInfo& info : e.infos) {
    const char flags = static_cast<char>((info.success ? kSuccess : 0) | (info.collision ? kCollision : 0) |
                                         (info.out_of_bounds ? kOutOfBounds : 0));
    body.put(flags);
  }
  std::ostringstream record;
  write_u32(record, demo_layout::record_magic);
  write_string(record, body.str());
  std::string out = record.str();
  out += u64_bytes(fnv1a64(out));
  return out;
}

CommitRecord read_commit_record(std::string_view bytes, std::uint64_t file_size, const std::string& source) {
  using namespace demo_layout;
  const bool magic_ok = std::memcmp(bytes.data(), magic, std::min(bytes.size(), sizeof magic)) == 0;
  if (!magic_ok || bytes.empty())
    throw Error(source + ": not an rdsim demonstration file (wrong magic bytes; expected a file written by "
                         "`rdsim teleop --record` or `rdsim demos record`)");
  if (bytes.size() < header_offset) throw Error(source + ": file is truncated (shorter than the file header)");
  CommitRecord c;
  Reader top(bytes, sizeof magic, header_offset, source);
  c.version = top.get<std::uint32_t>("the version");
  top.get<std::uint32_t>("the reserved field");
  c.committed = top.get<std::uint64_t>("the committed length");
  c.episodes = top.get<std::uint64_t>("the episode count");
  const auto commit_sum = top.get<std::uint64_t>("the commit checksum");
  if (commit_sum != fnv1a64(bytes.substr(0, commit_offset + 16)))
    throw Error(source + ": file is damaged (checksum mismatch in the commit record)");
  if (c.version != demo_format_version)
    throw Error(source + ": demonstration format version " + std::to_string(c.version) +
                " is not supported (this rdsim reads version " + std::to_string(demo_format_version) + ")");
  if (c.committed < header_offset) throw Error(source + ": file is damaged (its committed length is too small)");
  if (c.committed > file_size)
    throw Error(source + ": file is truncated (it holds " + std::to_string(file_size) + " bytes, its commit record says " +
                std::to_string(c.committed) + ")");
  return c;
}

DemoFile decode_demo_file(std::string_view bytes, const std::string& source) {
  using namespace demo_layout;
  const CommitRecord commit = read_commit_record(bytes, bytes.size(), source);
  const std::uint64_t committed = commit.committed, episodes = commit.episodes;
  DemoFile file;
  file.path = source;
  file.version = commit.version;
  file.interrupted_bytes = bytes.size() - committed;

  Reader r(bytes, header_offset, static_cast<std::size_t>(committed), source);
  const auto header_size = r.get<std::uint64_t>("the header length");
  const std::string_view header_text = r.take(header_size, "the header");
  const auto header_sum = r.get<std::uint64_t>("the header checksum");
  if (header_sum != fnv1a64(bytes.substr(header_offset, 8 + header_size)))
    throw Error(source + ": file is damaged (checksum mismatch in the header)");
  json header;
  try {
    header = json::parse(header_text);
  } catch (const json::exception&) {
    throw Error(source + ": file is damaged (its header is not valid JSON)");
  }
  if (!header.is_object() || header.value("format", "") != "rdsim demonstrations" || !header.contains("env") ||
      !header["env"].is_object() || !header.contains("spec") || !header.contains("rdsim_version") ||
      !header["rdsim_version"].is_string())
    throw Error(source + ": file is damaged (its header lacks format, rdsim_version, env or spec)");
  file.rdsim_version = header["rdsim_version"].get<std::string>();
  file.env_config = header["env"];
  file.spec = spec_from_json(header["spec"], source + ": header");

  while (r.left() > 0) {
    const std::string where = source + ": episode " + std::to_string(file.episodes.size() + 1);
    const std::size_t start = r.pos();
    if (r.get<std::uint32_t>("an episode record") != record_magic)
      throw Error(where + ": file is damaged (no episode record starts here)");
    const auto body_size = r.get<std::uint64_t>("an episode's length");
    const std::string_view body = r.take(body_size, "an episode");
    const std::size_t end = r.pos();
    if (r.get<std::uint64_t>("an episode's checksum") != fnv1a64(bytes.substr(start, end - start)))
      throw Error(where + ": file is damaged (checksum mismatch)");
    file.episodes.push_back(decode_episode(body, file, where));
  }
  if (file.episodes.size() != episodes)
    throw Error(source + ": file is damaged (the commit record counts " + std::to_string(episodes) + " episodes, the file holds " +
                std::to_string(file.episodes.size()) + ")");
  return file;
}

DemoFile read_demo_file(const std::string& path) {
  require_file_or_hint(path, "rdsim demos record --config TRAINING_CONFIG.json --out " + path + " (or --env NAME)");
  InputFile file(path, max_demo_file_bytes);  // a regular file (core/input_file.hpp)
  // The file header and its commit record before the body: a foreign or damaged file is refused
  // having read 40 bytes, and only the committed bytes are read.
  std::string bytes = file.read(demo_layout::header_offset);
  const CommitRecord commit = read_commit_record(bytes, file.size(), path);
  bytes += file.read(commit.committed - bytes.size());
  if (bytes.size() < commit.committed)
    throw Error(path + ": file is truncated (it was cut short while it was read)");
  DemoFile out = decode_demo_file(bytes, path);
  out.interrupted_bytes = file.size() - commit.committed;
  return out;
}

}  // namespace rdsim
