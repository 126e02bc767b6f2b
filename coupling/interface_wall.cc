#include "coupling/interface_wall.h"

#include <array>
#include <cmath>
#include <string>

#include "common/input_error.h"

namespace trackbed::coupling {

namespace {

// Every process's interface triangles in rank order: 12 numbers each (three corners, then the
// outward normal), and where each process's triangles begin.
std::vector<double> gather_triangles(const std::vector<fem::InterfaceTriangle>& local,
                                     MPI_Comm communicator, std::vector<int>& first_of_rank) {
  std::vector<double> mine;
  for (const auto& t : local) {
    for (const auto& corner : t.vertices) mine.insert(mine.end(), corner.begin(), corner.end());
    mine.insert(mine.end(), t.normal.begin(), t.normal.end());
  }
  int size = 0;
  MPI_Comm_size(communicator, &size);
  std::vector<int> counts(size), displacements(size + 1, 0);
  const int count = static_cast<int>(mine.size());
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, communicator);
  for (int r = 0; r < size; ++r) displacements[r + 1] = displacements[r] + counts[r];
  std::vector<double> all(displacements[size]);
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displacements.data(),
                 MPI_DOUBLE, communicator);
  first_of_rank.resize(size + 1);
  for (int r = 0; r <= size; ++r) first_of_rank[r] = displacements[r] / 12;
  return all;
}

}  // namespace

InterfaceWall::InterfaceWall(fem::BoundaryInterface& interface, const std::string& boundary_name,
                             MPI_Comm communicator)
    : interface_(interface), communicator_(communicator) {
  std::vector<int> first_of_rank;
  const std::vector<double> all =
      gather_triangles(interface.triangles(), communicator, first_of_rank);
  const int n = static_cast<int>(all.size() / 12);
  if (n == 0)
    throw InputError("coupling: the FE boundary '" + boundary_name +
                     "' has no face; valid: a boundary of the FE mesh that the ballast touches");
  // Corner order k of the FE triangle behind each wall triangle's corner (1 and 2 swapped where
  // the FE corners run clockwise seen from outside).
  std::vector<std::array<int, 3>> fe_corner(n);
  for (int t = 0; t < n; ++t) {
    const double* d = &all[12 * t];
    const dem::Vec3 a(d[0], d[1], d[2]), b(d[3], d[4], d[5]), c(d[6], d[7], d[8]);
    const dem::Vec3 outward(d[9], d[10], d[11]);
    const double alignment = (b - a).cross(c - a).normalized().dot(outward);
    if (!(std::abs(alignment) > 0.5))
      throw InputError("coupling: triangle " + std::to_string(t) + " of the FE boundary '" +
                       boundary_name +
                       "' does not face along its outward normal; valid: a boundary of flat or "
                       "gently curved faces");
    fe_corner[t] = alignment > 0 ? std::array<int, 3>{{0, 1, 2}} : std::array<int, 3>{{0, 2, 1}};
    const int base = static_cast<int>(mesh_.vertices.size());
    for (int k : fe_corner[t]) mesh_.vertices.emplace_back(d[3 * k], d[3 * k + 1], d[3 * k + 2]);
    mesh_.triangles.push_back({{base, base + 1, base + 2}});
  }
  mesh_.part_names = {boundary_name};
  mesh_.finalize();  // merges the corners the triangles share: one vertex each, no seams

  // Each vertex is owned by its first occurrence, on the lowest rank that has it.
  int rank = 0;
  MPI_Comm_rank(communicator, &rank);
  std::vector<bool> seen(mesh_.vertices.size(), false);
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh_.triangles[t][k];
      if (seen[v]) continue;
      seen[v] = true;
      if (t < first_of_rank[rank] || t >= first_of_rank[rank + 1]) continue;
      fem::TrianglePoint point{static_cast<std::size_t>(t - first_of_rank[rank]), {{0, 0, 0}}};
      point.barycentric[fe_corner[t][k]] = 1;
      owned_.push_back(v);
      owned_points_.push_back(point);
    }
}

void InterfaceWall::apply_vertex_loads(const std::vector<dem::Vec3>& loads) {
  std::vector<fem::PointForce> forces;
  forces.reserve(owned_.size());
  for (std::size_t i = 0; i < owned_.size(); ++i) {
    const dem::Vec3& f = loads[owned_[i]];
    forces.push_back({owned_points_[i], {{f.x(), f.y(), f.z()}}});
  }
  interface_.clear_forces();
  interface_.add_forces(forces);
}

void InterfaceWall::vertex_motion(std::vector<dem::Vec3>& displacement,
                                  std::vector<dem::Vec3>& velocity) const {
  // Each vertex has one owner and zeros elsewhere, so the sum over processes is exact.
  const std::size_t nv = mesh_.vertices.size();
  std::vector<double> local(6 * nv, 0.0), all(6 * nv);
  const auto motion = interface_.motion(owned_points_);
  for (std::size_t i = 0; i < owned_.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      local[6 * owned_[i] + c] = motion[i][0][c];
      local[6 * owned_[i] + 3 + c] = motion[i][1][c];
    }
  MPI_Allreduce(local.data(), all.data(), static_cast<int>(all.size()), MPI_DOUBLE, MPI_SUM,
                communicator_);
  displacement.resize(nv);
  velocity.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    displacement[v] = dem::Vec3(all[6 * v], all[6 * v + 1], all[6 * v + 2]);
    velocity[v] = dem::Vec3(all[6 * v + 3], all[6 * v + 4], all[6 * v + 5]);
  }
}

}  // namespace trackbed::coupling
