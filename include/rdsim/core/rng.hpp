#pragma once
#include <cmath>
#include <cstdint>

namespace rdsim {

// The one random number generator of rdsim (xoshiro256**, seeded through splitmix64).
// Our own uniform/normal transforms keep streams identical across standard libraries,
// so the same config and seed give the same numbers bit for bit.
class Rng {
public:
  explicit Rng(std::uint64_t seed = 0) { reseed(seed); }

  void reseed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& word : s_) word = splitmix64(x);
    has_spare_ = false;
  }

  // An independent generator for a sub-component (env, sampler, ...), derived from this
  // seed and a stream id so that adding a consumer does not shift everyone else's numbers.
  static Rng derive(std::uint64_t seed, std::uint64_t stream) {
    std::uint64_t x = seed ^ (0x9E3779B97F4A7C15ull * (stream + 1));
    return Rng(splitmix64(x));
  }

  std::uint64_t next_u64() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  // Uniform in [0, 1).
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  // Uniform integer in [0, n).
  std::uint64_t below(std::uint64_t n) { return n == 0 ? 0 : next_u64() % n; }

  // Standard normal (Marsaglia polar method).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double m = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * m;
    has_spare_ = true;
    return u * m;
  }
  double normal(double mean, double stddev) { return mean + stddev * normal(); }

private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  static std::uint64_t splitmix64(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  std::uint64_t s_[4]{};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// Stream ids for Rng::derive(seed, id). Fixed numbers, so adding a consumer never shifts the
// numbers another one draws. Env i uses `env_base + i`.
namespace rng_stream {
inline constexpr std::uint64_t network_init = 1;
inline constexpr std::uint64_t action_sampling = 2;
inline constexpr std::uint64_t minibatch_shuffle = 3;
inline constexpr std::uint64_t replay_sampling = 4;   // off-policy replay buffers
inline constexpr std::uint64_t exploration = 5;       // epsilon-greedy draws, warm-up actions, action noise
inline constexpr std::uint64_t evaluation = 6;        // `rdsim replay --stochastic`
inline constexpr std::uint64_t training_noise = 7;    // noise inside gradient steps (SAC actions, TD3 smoothing)
inline constexpr std::uint64_t perturbations = 8;     // ARS directions, CMA-ES candidates
inline constexpr std::uint64_t demonstrations = 9;    // demonstration splits, pre-training minibatches
inline constexpr std::uint64_t randomization = 10;    // an env's domain randomization (observation noise)
inline constexpr std::uint64_t episode_randomization = 11;  // its per-episode draws (masses, cameras, ...)
inline constexpr std::uint64_t demonstration_starts = 12;   // which training episodes start from a demonstration's state
inline constexpr std::uint64_t recording_noise = 13;       // `rdsim demos record --action-noise` (per episode seed)
inline constexpr std::uint64_t missed_grasps = 14;         // `rdsim demos record --missed-grasps` (per episode seed)
inline constexpr std::uint64_t env_base = 1000;
inline constexpr std::uint64_t mpi_rank_base = 1'000'000;  // rank r > 0 of an MPI job: its seed
}  // namespace rng_stream

}  // namespace rdsim
