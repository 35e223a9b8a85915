#include "rdsim/training/saved_policy.hpp"

#include <sstream>

#include "rdsim/core/error.hpp"

namespace rdsim {

SavedPolicy load_saved_policy(const std::string& path) {
  const ModelFile file = read_model_file(path);
  SavedPolicy p;
  p.config = parse_train_config(file.config, path + " (embedded config)", "model");
  p.spec = config_spec(p.config);
  check_model_spec(file, p.spec, path);
  p.algorithm = make_algorithm(p.config.algorithm, p.config.seed, p.spec);
  std::istringstream in(file.payload);
  p.algorithm->load(in, false, path);  // a checkpoint's payload starts with the same weights
  if (file.kind == ModelKind::Model && in.peek() != std::char_traits<char>::eof())
    throw Error(path + ": file is damaged (unexpected trailing data after the weights)");
  return p;
}

}  // namespace rdsim
