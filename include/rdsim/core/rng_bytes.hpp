#pragma once
#include <cstring>
#include <string>
#include <type_traits>

#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"

// An Rng's complete state as bytes (checkpoints), without widening Rng's interface. Only
// meaningful on the machine/build that wrote it, which is all a checkpoint promises.
namespace rdsim {

static_assert(std::is_trivially_copyable_v<Rng>, "Rng state is copied as bytes");

inline std::string rng_to_bytes(const Rng& rng) {
  std::string bytes(sizeof(Rng), '\0');
  std::memcpy(bytes.data(), &rng, sizeof(Rng));
  return bytes;
}

inline Rng rng_from_bytes(const std::string& bytes, const std::string& source) {
  if (bytes.size() != sizeof(Rng)) throw Error(source + ": random generator state has the wrong size");
  Rng rng;
  std::memcpy(&rng, bytes.data(), sizeof(Rng));
  return rng;
}

}  // namespace rdsim
