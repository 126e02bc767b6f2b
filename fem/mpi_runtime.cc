#include "fem/mpi_runtime.h"

#include <deal.II/base/mpi.h>

namespace trackbed::fem {

struct MpiRuntime::Impl {
  Impl(int& argc, char**& argv) : mpi(argc, argv, 1) {}
  dealii::Utilities::MPI::MPI_InitFinalize mpi;
};

MpiRuntime::MpiRuntime(int& argc, char**& argv) : impl_(std::make_unique<Impl>(argc, argv)) {}
MpiRuntime::~MpiRuntime() = default;

}  // namespace trackbed::fem
