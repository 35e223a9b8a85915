#include "rdsim/training/data_parallel.hpp"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/checksum.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/rng.hpp"

namespace rdsim {
namespace {

constexpr char kTrailerMagic[8] = {'R', 'D', 'S', 'I', 'M', 'M', 'P', 'I'};
constexpr std::size_t kTrailerSize = 8 + sizeof kTrailerMagic;  // u64 extension size + magic

std::string weights_of(const Algorithm& algo) {
  std::ostringstream out;
  algo.save_all_weights(out);
  return out.str();
}

}  // namespace

std::uint64_t rank_seed(std::uint64_t seed, int rank) {
  if (rank == 0) return seed;
  return Rng::derive(seed, rng_stream::mpi_rank_base + static_cast<std::uint64_t>(rank)).next_u64();
}

long long run_timesteps(Communicator& comm, const VecEnv& vec) {
  if (comm.size() == 1) return vec.timesteps();
  const auto mine = static_cast<std::uint64_t>(vec.timesteps());
  std::vector<std::uint64_t> all(static_cast<std::size_t>(comm.size()));
  comm.allgather(&mine, 1, all.data());
  long long sum = 0;
  for (const std::uint64_t steps : all) sum += static_cast<long long>(steps);
  return sum;
}

void share_weights(Communicator& comm, Algorithm& algo) {
  if (comm.size() == 1) return;
  std::string weights = comm.rank() == 0 ? weights_of(algo) : std::string();
  comm.broadcast(weights, 0);
  if (comm.rank() == 0) return;
  std::istringstream in(weights);
  algo.load_all_weights(in, "rank 0's weights");
}

void check_data_parallel(Communicator& comm, const Algorithm& algo) {
  if (comm.size() == 1 || algo.data_parallel()) return;
  if (comm.rank() != 0) {
    // Open MPI ends this rank with SIGTERM when rank 0 aborts: die quietly, not with the
    // interrupt handler's "stopping after this update" (interrupt.cpp), so the report is rank 0's.
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    std::string never;
    comm.broadcast(never, 0);  // rank 0 throws instead of joining: its abort ends this rank here
    throw RankExit{2};
  }
  throw Error("mpi: algorithm \"" + algo.name() + "\" does not train data-parallel yet (under mpirun: ppo, a2c, dqn, "
              "sac, td3, ddpg, bc, random); run it as one process (without mpirun) and give it more cores "
              "with num_envs and num_threads");
}

void check_same_weights(Communicator& comm, const Algorithm& algo, long long updates) {
  if (comm.size() == 1) return;
  const std::uint64_t mine = fnv1a64(weights_of(algo));
  std::vector<std::uint64_t> all(static_cast<std::size_t>(comm.size()));
  comm.allgather(&mine, 1, all.data());
  for (int r = 1; r < comm.size(); ++r) {
    if (all[static_cast<std::size_t>(r)] == all[0]) continue;
    if (comm.rank() != 0) throw RankExit{1};
    char hashes[64];
    std::snprintf(hashes, sizeof hashes, "%016llx vs %016llx", static_cast<unsigned long long>(all[0]),
                  static_cast<unsigned long long>(all[static_cast<std::size_t>(r)]));
    throw Error("mpi: the weights of rank " + std::to_string(r) + " differ from rank 0's after update " +
                std::to_string(updates) + " (hash " + hashes + "): the ranks diverged, so the run stops. "
                "All ranks must run the same rdsim build on the same kind of CPU (a different instruction "
                "set rounds differently: build with -DRDSIM_NATIVE=OFF for a mixed cluster)");
  }
}

void on_every_rank(Communicator& comm, const std::function<void()>& step) {
  if (comm.size() == 1) {
    step();
    return;
  }
  std::uint64_t failed = 0;
  std::string message;
  try {
    step();
  } catch (const Error& e) {
    failed = 1;
    message = e.what();
  }
  std::vector<std::uint64_t> all(static_cast<std::size_t>(comm.size()));
  comm.allgather(&failed, 1, all.data());
  int first = -1;  // the first rank that failed
  for (int r = comm.size() - 1; r >= 0; --r)
    if (all[static_cast<std::size_t>(r)] != 0) first = r;
  if (first < 0) return;
  const std::vector<std::string> messages = comm.gather(message, 0);
  if (comm.rank() != 0) throw RankExit{1, true};
  if (first == 0) throw JobError(message);
  throw JobError("(MPI rank " + std::to_string(first) + ") " + messages[static_cast<std::size_t>(first)]);
}

RunEpisodes::RunEpisodes(Communicator& comm, int window, bool lockstep)
    : comm_(comm), lockstep_(lockstep), merged_(0, window) {}

std::vector<EpisodeRecord> RunEpisodes::take_finished(VecEnv& vec, long long steps_before) {
  std::vector<EpisodeRecord> mine = vec.episodes().take_finished();
  if (comm_.size() == 1) return mine;
  const std::vector<std::string> parts = comm_.gather(EpisodeTracker::encode(mine), 0);
  std::vector<EpisodeRecord> run;
  long long steps = steps_before;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    for (EpisodeRecord e : EpisodeTracker::decode(parts[r], "mpi: episodes of rank " + std::to_string(r))) {
      steps += e.length;
      e.timesteps = lockstep_ ? e.timesteps * comm_.size() : steps;
      merged_.add_finished(e);
    }
  }
  for (EpisodeRecord& e : merged_.take_finished()) run.push_back(e);
  return run;
}

EpisodeStats RunEpisodes::stats(const VecEnv& vec) const {
  return comm_.size() == 1 ? vec.episodes().stats() : merged_.stats();
}

long long RunEpisodes::episodes(const VecEnv& vec) const {
  return comm_.size() == 1 ? vec.episodes().episodes() : merged_.episodes();
}

void RunEpisodes::save(std::ostream& out) const { merged_.save(out); }

void RunEpisodes::load(std::istream& in, const std::string& source) { merged_.load(in, source); }

std::string gather_checkpoint(Communicator& comm, const std::string& payload, const RunEpisodes& episodes) {
  if (comm.size() == 1) return payload;
  const std::vector<std::string> parts = comm.gather(payload, 0);
  if (comm.rank() != 0) return {};
  std::ostringstream ext;
  write_u32(ext, static_cast<std::uint32_t>(comm.size()));
  std::ostringstream log;
  episodes.save(log);
  write_string(ext, log.str());
  for (std::size_t r = 1; r < parts.size(); ++r) write_string(ext, parts[r]);
  std::ostringstream out;
  out << parts[0] << ext.str();
  write_u64(out, ext.str().size());
  out.write(kTrailerMagic, sizeof kTrailerMagic);
  return out.str();
}

std::string checkpoint_part(Communicator& comm, const std::string& payload, RunEpisodes& episodes,
                            const std::string& source) {
  // A single-process checkpoint has no extension: it ends without the trailer.
  std::uint32_t ranks = 1;
  std::string own = payload, extension;
  if (payload.size() >= kTrailerSize &&
      std::memcmp(payload.data() + payload.size() - sizeof kTrailerMagic, kTrailerMagic, sizeof kTrailerMagic) == 0) {
    std::istringstream size_in(payload.substr(payload.size() - kTrailerSize, 8));
    const std::uint64_t n = read_u64(size_in, source);
    if (n > payload.size() - kTrailerSize) throw Error(source + ": file is damaged (bad MPI extension)");
    const std::size_t own_size = payload.size() - kTrailerSize - static_cast<std::size_t>(n);
    extension = payload.substr(own_size, static_cast<std::size_t>(n));
    own = payload.substr(0, own_size);
    std::istringstream in(extension);
    ranks = read_u32(in, source);
  }
  if (static_cast<int>(ranks) != comm.size()) {
    throw Error(source + ": written by a run of " + std::to_string(ranks) + " process" + (ranks == 1 ? "" : "es") +
                "; resume it with " + (ranks == 1 ? std::string("one process (no mpirun)") : "mpirun -np " + std::to_string(ranks)) +
                ", not " + std::to_string(comm.size()));
  }
  if (ranks == 1) return own;
  std::istringstream in(extension);
  (void)read_u32(in, source);
  std::istringstream log(read_string(in, source));
  episodes.load(log, source);
  std::vector<std::string> others;
  for (std::uint32_t r = 1; r < ranks; ++r) others.push_back(read_string(in, source));
  return comm.rank() == 0 ? own : others[static_cast<std::size_t>(comm.rank() - 1)];
}

}  // namespace rdsim
