// ParaView output: VTK XML unstructured grids (.vtu, binary appended data) and the .pvd
// collection that strings them into a time series. Format: docs/formats.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dem/engine/types.h"

namespace trackbed::dem {

class Simulation;

// A point/line/triangle grid with named point or cell data, written in one call.
struct VtuGrid {
  std::vector<Vec3> points;
  std::vector<std::int64_t> connectivity;  // point indices of every cell, concatenated
  std::vector<std::int64_t> offsets;       // end of each cell in `connectivity`
  std::vector<std::uint8_t> types;         // VTK cell types: 1 vertex, 3 line, 5 triangle
  struct Field {
    std::string name;
    int components;
    std::vector<double> values;
  };
  std::vector<Field> point_data, cell_data;

  void write(const std::string& path) const;  // atomic (temporary name, then rename)
};

// Spheres as points (radius, velocity, angular velocity, body, id, material, clump flag,
// displacement from `reference` if given, one entry per element).
VtuGrid particles_grid(const Simulation& sim, const std::vector<Vec3>* reference = nullptr);
// Force chains: one line per active contact from centre to centre (or to the wall contact
// point), with the contact force vector and its magnitude.
VtuGrid contacts_grid(const Simulation& sim);
// Walls: meshes as triangles; planes as squares around the point nearest the particles' centre,
// half as wide as the particles' bounding-box diagonal plus 0.1 m; the wall force as cell data.
VtuGrid walls_grid(const Simulation& sim);

// Appends (time, file) entries to a .pvd collection, rewriting it atomically each time.
class PvdCollection {
 public:
  explicit PvdCollection(std::string path) : path_(std::move(path)) {}
  // The collection of a resumed run: its entries so far, the file rewritten at the next add.
  PvdCollection(std::string path, std::vector<std::pair<double, std::string>> entries)
      : path_(std::move(path)), entries_(std::move(entries)) {}
  void add(double time, const std::string& relative_file);
  const std::vector<std::pair<double, std::string>>& entries() const { return entries_; }

 private:
  std::string path_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace trackbed::dem
