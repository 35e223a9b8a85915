#pragma once
#include <memory>

#include "rdsim/parallel/communicator.hpp"

// The communicator of this process for `rdsim train`: MPI when an MPI launcher started it with
// more than one rank (src/mpi), otherwise one process. A build without MPI started by
// `mpirun -np K` (K > 1) refuses with a message instead of running K unrelated copies.
namespace rdsim {

// rdsim::Error for the case above, or when MPI cannot start.
std::unique_ptr<Communicator> make_process_communicator();

// True when this build has the mpi library (CMake found MPI).
bool built_with_mpi();

}  // namespace rdsim
