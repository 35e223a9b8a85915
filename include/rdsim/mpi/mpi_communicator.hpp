#pragma once
#include <memory>

#include "rdsim/parallel/communicator.hpp"

// The Communicator of a job started by mpirun (Open MPI; any MPI-3 library): MPI_COMM_WORLD.
// This library is built only when CMake finds MPI (Debian: libopenmpi-dev); nothing else in rdsim
// includes mpi.h.
namespace rdsim {

// Initialises MPI (MPI_THREAD_FUNNELED: only the thread that made it calls MPI; VecEnv's workers
// never do) and finalises it when the communicator goes away. One per process.
// rdsim::Error when MPI cannot start.
std::unique_ptr<Communicator> make_mpi_communicator();

}  // namespace rdsim
