#pragma once
// A stand-in for an MPI job in algorithm tests: rank 0 of `size` ranks whose other ranks all
// contribute `mirror` times this rank's values to every sum (mirror = 1: identical ranks).
#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "rdsim/parallel/communicator.hpp"

namespace toy {

class FakeCommunicator final : public rdsim::Communicator {
public:
  explicit FakeCommunicator(int size, float mirror = 1.0f) : size_(size), mirror_(mirror) {}
  int rank() const override { return 0; }
  int size() const override { return size_; }
  int local_size() const override { return size_; }
  std::string name() const override { return "fake"; }
  [[noreturn]] void abort(int code) override { std::exit(code); }

protected:
  void do_allreduce_sum(float* d, std::size_t n) override {
    for (std::size_t i = 0; i < n; ++i) d[i] += static_cast<float>(size_ - 1) * mirror_ * d[i];
  }
  void do_allreduce_sum(double* d, std::size_t n) override {
    for (std::size_t i = 0; i < n; ++i) d[i] += static_cast<double>(size_ - 1) * mirror_ * d[i];
  }
  void do_allgather(const void* send, std::size_t bytes, void* recv) override {
    for (int r = 0; r < size_; ++r) std::memcpy(static_cast<char*>(recv) + static_cast<std::size_t>(r) * bytes, send, bytes);
  }
  void do_broadcast(std::string&, int) override {}
  std::vector<std::string> do_gather(const std::string& bytes, int) override {
    return std::vector<std::string>(static_cast<std::size_t>(size_), bytes);
  }

private:
  int size_;
  float mirror_;
};

}  // namespace toy
