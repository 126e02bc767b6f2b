// MPI, p4est and Trilinos for the lifetime of a process that builds an ElasticBody (deal.II's
// MPI_InitFinalize behind a pointer, so that a program's main() needs no deal.II header). One
// per process, before any ElasticBody; the DEM's OpenMP threads do not call MPI (funneled).
#pragma once

#include <mpi.h>

#include <memory>

namespace trackbed::fem {

class MpiRuntime {
 public:
  MpiRuntime(int& argc, char**& argv);
  ~MpiRuntime();
  MpiRuntime(const MpiRuntime&) = delete;
  MpiRuntime& operator=(const MpiRuntime&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace trackbed::fem
