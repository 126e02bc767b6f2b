#include "dem/io/particle_file.h"

#include <cmath>

#include "common/input_error.h"
#include "dem/io/csv_table.h"

namespace trackbed::dem {

void read_particle_file(const std::string& path, const MaterialTable& materials,
                        const std::map<std::string, ClumpTemplate>& templates,
                        Particles& particles) {
  const CsvTable csv(path);
  for (const char* c : {"x", "y", "z"}) csv.require(c);
  if (csv.num_rows() == 0)
    throw InputError(path + ": no particles; valid: at least one row after the header");
  // Scaled templates are cached: a sample uses a few scales of many templates.
  std::map<std::pair<std::string, double>, ClumpTemplate> scaled_cache;

  for (int row = 0; row < csv.num_rows(); ++row) {
    const int line = csv.line_of(row);
    const Vec3 x(csv.number(row, "x"), csv.number(row, "y"), csv.number(row, "z"));
    int mat = 0;
    if (csv.has("material") && !csv.text(row, "material").empty()) {
      try {
        mat = materials.index_of(csv.text(row, "material"));
      } catch (const InputError& e) {
        throw input_error_at(path, line, e.what());
      }
    }
    const double density = materials[mat].density;
    const std::string tname = csv.has("template") ? csv.text(row, "template") : "";
    const std::int64_t user_id = row;
    int b;
    if (tname.empty()) {
      if (!csv.has("radius")) csv.require("radius");
      const double r = csv.number(row, "radius");
      if (!(r > 0))
        throw input_error_at(path, line,
                             "radius must be > 0 (metres), got " + csv.text(row, "radius"));
      b = particles.add_ball(x, r, mat, density, user_id);
    } else {
      const auto it = templates.find(tname);
      if (it == templates.end()) {
        std::string known;
        for (const auto& [name, t] : templates) known += (known.empty() ? "" : ", ") + name;
        throw input_error_at(path, line,
                             "unknown clump template '" + tname +
                                 "'; defined templates: " + (known.empty() ? "(none)" : known));
      }
      const double s = csv.number_or(row, "scale", 1.0);
      if (!(s > 0))
        throw input_error_at(path, line, "scale must be > 0, got " + csv.text(row, "scale"));
      Quat q(csv.number_or(row, "qw", 1.0), csv.number_or(row, "qx", 0.0),
             csv.number_or(row, "qy", 0.0), csv.number_or(row, "qz", 0.0));
      if (!(q.norm() > 1e-12))
        throw input_error_at(path, line, "quaternion (qw, qx, qy, qz) has zero length");
      q.normalize();
      auto key = std::make_pair(tname, s);
      auto cached = scaled_cache.find(key);
      if (cached == scaled_cache.end())
        cached = scaled_cache.emplace(key, s == 1.0 ? it->second : scaled(it->second, s)).first;
      const ClumpTemplate& t = cached->second;
      // Template frame -> world: centroid and principal axes move with (x, q).
      const Vec3 centre = x + q * t.input_centroid;
      const Quat orientation = q * Quat(t.input_axes);
      b = particles.add_clump(t, centre, orientation, mat, density, user_id);
    }
    particles.v[b] =
        Vec3(csv.number_or(row, "vx", 0), csv.number_or(row, "vy", 0), csv.number_or(row, "vz", 0));
    particles.w[b] =
        Vec3(csv.number_or(row, "wx", 0), csv.number_or(row, "wy", 0), csv.number_or(row, "wz", 0));
  }
}

}  // namespace trackbed::dem
