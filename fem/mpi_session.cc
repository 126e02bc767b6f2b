#include "fem/mpi_session.h"

#include <deal.II/base/mpi.h>

namespace trackbed::fem {

struct MpiSession::Impl {
  Impl(int& argc, char**& argv) : session(argc, argv, 1) {}
  dealii::Utilities::MPI::MPI_InitFinalize session;
};

MpiSession::MpiSession(int& argc, char**& argv) : impl_(std::make_unique<Impl>(argc, argv)) {}
MpiSession::~MpiSession() = default;

}  // namespace trackbed::fem
