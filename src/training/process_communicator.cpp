#include "rdsim/training/process_communicator.hpp"

#include "rdsim/core/error.hpp"
#ifdef RDSIM_HAVE_MPI
#include "rdsim/mpi/mpi_communicator.hpp"
#endif

namespace rdsim {

bool built_with_mpi() {
#ifdef RDSIM_HAVE_MPI
  return true;
#else
  return false;
#endif
}

std::unique_ptr<Communicator> make_process_communicator() {
  const int world = launcher_world_size().value_or(1);
#ifdef RDSIM_HAVE_MPI
  if (world > 1) return make_mpi_communicator();
#else
  if (world > 1)
    throw Error("this rdsim was built without MPI (CMake did not find it; Debian: apt-get install "
                "libopenmpi-dev openmpi-bin, then rebuild with tools/setup.sh), so `mpirun -np " +
                std::to_string(world) + "` would run " + std::to_string(world) +
                " unrelated copies of one training run; run it without mpirun");
#endif
  return make_single_process_communicator();
}

}  // namespace rdsim
