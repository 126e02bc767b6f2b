// The broad phase of mesh contacts: a uniform grid that finds the triangles near a sphere.
#pragma once

#include <array>
#include <vector>

#include "dem/engine/triangle_mesh.h"
#include "dem/engine/types.h"

namespace trackbed::dem {

// A uniform grid over a mesh's bounding box; each triangle is registered in every cell its
// bounding box overlaps. A query visits only the cells the sphere's bounding box overlaps and
// returns, sorted and without repeats, the triangles whose bounding box comes within radius of
// the centre: a superset of the triangles closer than radius. The grid holds the vertex
// positions at build time: rebuild when the mesh moves, or query with the radius enlarged by the
// largest vertex displacement since the build.
class TriangleGrid {
 public:
  // cell > 0; a cell about the size of the triangles or of the particles is a good choice. The
  // cell is enlarged if the grid would need more than kMaxCells cells.
  void build(const TriangleMesh& mesh, double cell);
  void query(const Vec3& centre, double radius, std::vector<int>& out) const;

  double cell_size() const { return cell_; }

  static constexpr long kMaxCells = 1L << 26;  // 64 Mi cells, 256 MiB of offsets

 private:
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 0.0;
  std::array<int, 3> dims_{{0, 0, 0}};
  std::vector<int> cell_offsets_;  // CSR: triangles of cell c in items_[offsets[c], offsets[c+1])
  std::vector<int> items_;
  std::vector<Vec3> box_lower_;  // triangle bounding boxes at build time
  std::vector<Vec3> box_upper_;
};

}  // namespace trackbed::dem
