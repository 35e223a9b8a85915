// Keyword options of rdsim.make / make_vec -> EnvConfig, through the config file's reader.
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "rdsim/core/config_reader.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/envs/registry.hpp"

namespace rdsim::python {
namespace {

// A Python option value as the JSON a config file would hold; rdsim::Error for other types.
nlohmann::json json_value(const std::string& where, const std::string& key, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) {
    // Beyond 64 bits the reader would see a rounded number: say so instead.
    try {
      return value.cast<long long>();
    } catch (const py::cast_error&) {
      throw Error(where + ": " + key + ": expected a number in range, got an integer beyond 64 bits");
    }
  }
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  // Lists (home_pose, joints, ...): a list or tuple of the values above, or a 1-D NumPy array.
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json list = nlohmann::json::array();
    for (const py::handle item : value) list.push_back(json_value(where, key, item));
    return list;
  }
  // Option objects ("randomize": {...}): a dict of string keys and the values above.
  if (py::isinstance<py::dict>(value)) {
    nlohmann::json object = nlohmann::json::object();
    for (const auto& [k, v] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k)) throw Error(where + ": " + key + ": expected string keys, got a Python " + type_name(k));
      const std::string name = k.cast<std::string>();
      object[name] = json_value(where, key + "." + name, v);
    }
    return object;
  }
  if (py::hasattr(value, "tolist") && py::hasattr(value, "dtype") && py::len(value.attr("shape")) == 1)
    return json_value(where, key, value.attr("tolist")());
  // NumPy scalars (np.int64(5), np.float32(0.1), np.bool_) read as the Python values they hold.
  if (py::hasattr(value, "item") && py::hasattr(value, "dtype") && py::len(value.attr("shape")) == 0)
    return json_value(where, key, value.attr("item")());
  throw Error(where + ": " + key + ": expected a number, true/false, a string, or a list or dict of them, got a Python " +
              type_name(value));
}

}  // namespace

EnvConfig env_config_from_options(const std::string& name, const py::dict& options, const std::string& where) {
  nlohmann::json json = nlohmann::json::object();
  json["name"] = name;
  for (const auto& [k, v] : options) {
    const std::string key = py::str(k).cast<std::string>();
    if (key == "name") throw Error(where + ": name: is given by the env id, not as an option");
    json[key] = json_value(where, key, v);
  }
  ConfigReader reader(json, where);
  EnvConfig config = read_env_config(reader);
  reader.finish();
  return config;
}

std::string env_config_json(const EnvConfig& config) { return to_json(config).dump(); }

}  // namespace rdsim::python
