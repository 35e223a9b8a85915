#pragma once
#include <cstddef>
#include <cstring>
#include <string>
#include <type_traits>

#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"

// An Rng's complete state as bytes (checkpoints), without widening Rng's interface. Only
// meaningful on the machine/build that wrote it, which is all a checkpoint promises.
namespace rdsim {

static_assert(std::is_trivially_copyable_v<Rng>, "Rng state is copied as bytes");
// Rng's members: u64 s_[4] (bytes 0-31), double spare_ (32-39), bool has_spare_ (40), then padding.
inline constexpr std::size_t kRngFlagByte = 40;
static_assert(sizeof(Rng) == 48, "rng_bytes.hpp assumes Rng's layout");

inline std::string rng_to_bytes(const Rng& rng) {
  std::string bytes(sizeof(Rng), '\0');
  std::memcpy(bytes.data(), &rng, kRngFlagByte + 1);  // not the padding: equal states give equal bytes
  return bytes;
}

inline Rng rng_from_bytes(const std::string& bytes, const std::string& source) {
  if (bytes.size() != sizeof(Rng)) throw Error(source + ": random generator state has the wrong size");
  if (static_cast<unsigned char>(bytes[kRngFlagByte]) > 1) throw Error(source + ": random generator state is damaged");
  Rng rng;
  std::memcpy(static_cast<void*>(&rng), bytes.data(), kRngFlagByte + 1);
  return rng;
}

}  // namespace rdsim
