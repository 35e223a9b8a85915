#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

// The processes of one training job and the collective operations between them: what data-
// parallel training needs, behind an interface so that nothing but src/mpi includes mpi.h.
// `rdsim train` under `mpirun -np K` gets an MPI communicator (src/mpi, built when MPI is found);
// everywhere else it is single_process_communicator(): rank 0 of 1, every operation a no-op.
//
// Every operation is collective: all ranks call it, in the same order, with the same sizes. An
// algorithm gets the job's communicator through Algorithm::set_communicator (algorithm.hpp).
//
// Data-parallel gradient methods (PPO, A2C, DQN, SAC, TD3, DDPG): every rank steps its own envs, computes the
// gradient of its own minibatch, and average_gradients() (algorithms/gradient_averaging.hpp) sums
// them with allreduce_sum and divides by size(), so every rank applies the same step and the
// parameters stay identical (the training loop compares a hash of them across ranks).
//
// Gradient-free population methods (ARS, CMA-ES) spread the population over the ranks: every
// rank draws the same candidates (same search state), evaluates its share, and allgather() hands
// every rank all returns, so every rank makes the same update (evaluate_population_on_ranks,
// algorithms/population.hpp). TRPO also averages its Fisher-vector products and line-search
// values (average_values, algorithms/gradient_averaging.hpp).
namespace rdsim {

class Communicator {
public:
  virtual ~Communicator() = default;

  virtual int rank() const = 0;        // 0 .. size()-1; rank 0 writes the run's files
  virtual int size() const = 0;        // ranks in the job
  virtual int local_size() const = 0;  // ranks on this machine (they share its cores)
  virtual std::string name() const = 0;  // "single process", "mpi"

  // Element-wise sum over all ranks, in place; every rank ends with the same bits.
  void allreduce_sum(float* data, std::size_t n);
  void allreduce_sum(double* data, std::size_t n);
  // Rank r's n values land at recv[r * n .. r * n + n) on every rank (recv holds size() * n).
  void allgather(const double* send, std::size_t n, double* recv);
  void allgather(const std::uint64_t* send, std::size_t n, std::uint64_t* recv);
  // `root`'s bytes replace everyone's (the sizes may differ before the call).
  void broadcast(std::string& bytes, int root = 0);
  // Every rank's bytes in rank order at `root`; an empty list on the other ranks.
  std::vector<std::string> gather(const std::string& bytes, int root = 0);
  // Ends every process of the job with `exit_code`: after an error on one rank, so that the
  // others do not wait forever in a collective. Single process: std::exit.
  [[noreturn]] virtual void abort(int exit_code) = 0;

  // What allreduce_sum moved so far (payload bytes this rank contributed; nothing for one rank).
  struct Traffic {
    long long calls = 0;
    long long bytes = 0;
    double seconds = 0.0;
  };
  const Traffic& allreduce_traffic() const { return traffic_; }

protected:
  virtual void do_allreduce_sum(float* data, std::size_t n) = 0;
  virtual void do_allreduce_sum(double* data, std::size_t n) = 0;
  virtual void do_allgather(const void* send, std::size_t bytes_each, void* recv) = 0;
  virtual void do_broadcast(std::string& bytes, int root) = 0;
  virtual std::vector<std::string> do_gather(const std::string& bytes, int root) = 0;

private:
  template <class Reduce>
  void count(std::size_t bytes, Reduce reduce);  // times one allreduce into traffic_

  Traffic traffic_;
};

// The communicator of a process that is the whole job (no MPI): rank 0 of 1. The first is one
// shared instance (what an algorithm uses unless told otherwise), the second a new one.
Communicator& single_process_communicator();
std::unique_ptr<Communicator> make_single_process_communicator();

// The world size an MPI launcher (mpirun/mpiexec of Open MPI, MPICH, Slurm's PMI) gave this
// process in its environment, or nothing when it was not started by one.
std::optional<int> launcher_world_size();
// This process's rank according to the launcher's environment (0 when unknown).
int launcher_rank();

}  // namespace rdsim
