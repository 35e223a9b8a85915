// A robot controller's side of a trained policy: load model.bin with rdsim_policy (no simulation,
// rendering or training code linked) and answer each observation with the policy's action.
// Observations come one per line on standard input (the env's float values, space-separated).
//   build/rdsim_policy_example runs/jaka_button/model.bin < observations.txt
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/policy/policy.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " MODEL.bin < observations\n";
    return 2;
  }
  try {
    const rdsim::Policy policy = rdsim::Policy::load(argv[1]);
    std::cerr << policy.algorithm() << " policy for " << policy.env_spec() << "\n";
    for (std::string line; std::getline(std::cin, line);) {
      std::istringstream fields(line);
      std::vector<float> observation;
      for (float v; fields >> v;) observation.push_back(v);
      const rdsim::Action action = policy.act(observation);
      if (policy.discrete()) std::cout << action.index << "\n";
      else std::cout << action.values.transpose() << "\n";
    }
  } catch (const rdsim::Error& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
}
