#pragma once
#include <string>
#include <vector>

// What a training run will allocate, estimated from its config BEFORE anything is allocated, so
// that a config asking for more memory than the machine has is one clear error naming the keys
// responsible, instead of a crash or a machine swapping for minutes. Each library adds the items
// it knows (envs: physics and images; algorithms: networks, buffers); the app compares the total
// with the limit (train --max-memory). Bytes are doubles: a silly config must not overflow them.
namespace rdsim {

struct MemoryItem {
  std::string what;  // "network weights and optimiser state (network.hidden_sizes)"
  double bytes = 0.0;
};

class MemoryEstimate {
public:
  void add(std::string what, double bytes);
  double total() const;
  const std::vector<MemoryItem>& items() const { return items_; }
  // "about 17.3 GB: network weights ... 17.2 GB, rollout buffer ... 12 MB" (largest first, at most
  // `max_items` named).
  std::string summary(std::size_t max_items = 3) const;

private:
  std::vector<MemoryItem> items_;
};

// 1536 -> "1.5 KB", 17.2e9 -> "17.2 GB" (decimal units, 3 significant digits).
std::string format_bytes(double bytes);

}  // namespace rdsim
