// The coupling surface of an ElasticBody: the faces of one named boundary as triangles, consistent
// nodal loads from point forces on them, and the motion of points on them.
//
// Each quadrilateral face of an element of degree p is split into p x p sub-quadrilaterals through
// its support points, each into two triangles, so the triangles follow the displacement field.
// A triangle remembers the reference-cell coordinates of its corners; a point with barycentric
// coordinates b has reference coordinates xi = sum_k b_k xi_k, where every shape function of the
// owning cell is evaluated. A point force F there adds F_c phi_i(xi) to every dof i of component
// c (the consistent load, equal to the work-equivalent load of a Dirac force); its displacement is
// sum_i U_i phi_i(xi). Triangles are those of locally owned cells: each process sees its part.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fem/elastic_body.h"

namespace trackbed::fem {

struct InterfaceTriangle {
  std::array<Vector3, 3> vertices;          // reference (undeformed) positions, m
  std::array<Vector3, 3> unit_cell_points;  // the same corners in the owning cell's unit cube
  std::string cell_id;                      // deal.II CellId of the owning cell, as text
  unsigned int face_no;                     // face of the owning cell, 0..5
  Vector3 normal;                           // outward unit normal
  double area;                              // m^2
};

// A point on a triangle: index into triangles() and barycentric coordinates (summing to 1).
struct TrianglePoint {
  std::size_t triangle;
  std::array<double, 3> barycentric;
};

struct PointForce {
  TrianglePoint where;
  Vector3 force;  // N
};

// One term of u_c(x) = sum weight * U[dof]: the shape-function weights of a point.
struct ShapeWeight {
  std::uint64_t dof;       // global degree of freedom
  unsigned int component;  // 0, 1, 2 = x, y, z
  double weight;           // phi_dof(x)
};

class BoundaryInterface {
 public:
  // The body must be set up; the interface stays valid until the next setup().
  BoundaryInterface(ElasticBody& body, const std::string& boundary_name);
  ~BoundaryInterface();

  const std::vector<InterfaceTriangle>& triangles() const;
  Vector3 position(const TrianglePoint& point) const;  // reference position, m
  std::vector<ShapeWeight> shape_weights(const TrianglePoint& point) const;
  // Adds consistent nodal loads to the body's interface load (used by the next solve). Collective.
  void add_forces(const std::vector<PointForce>& forces);
  // Clears the interface load of the body. Collective.
  void clear_forces();
  // Displacement and velocity of points on this process's triangles (no communication).
  std::vector<std::array<Vector3, 2>> motion(const std::vector<TrianglePoint>& points) const;

 private:
  // The triangle of a point; throws InputError for an index out of range.
  const InterfaceTriangle& triangle(const TrianglePoint& point) const;
  ElasticBody& body_;
  struct Data;
  std::unique_ptr<Data> data_;
};

}  // namespace trackbed::fem
