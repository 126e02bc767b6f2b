#include "dem/engine/particles.h"

#include <algorithm>
#include <cmath>

#include "dem/engine/value_checks.h"

namespace trackbed::dem {

int Particles::num_clumps() const {
  return static_cast<int>(std::count(is_clump.begin(), is_clump.end(), 1));
}

std::string Particles::defect(int num_materials) const {
  const std::size_t nb = x.size(), ne = pos.size();
  for (std::size_t n : {v.size(), q.size(), w.size(), L.size(), f.size(), t.size(), mass.size(),
                        inertia.size(), body_material.size(), id.size(), is_clump.size()})
    if (n != nb) return "the body arrays differ in length";
  for (std::size_t n : {offset.size(), radius.size(), body.size(), material.size()})
    if (n != ne) return "the element arrays differ in length";
  if (first_element.size() != nb + 1 || first_element.front() != 0 ||
      static_cast<std::size_t>(first_element.back()) != ne)
    return "first_element does not split the " + std::to_string(ne) + " elements among the " +
           std::to_string(nb) + " bodies";
  auto material_ok = [&](int m) { return m >= 0 && m < num_materials; };
  for (std::size_t b = 0; b < nb; ++b) {
    const std::string which = "body " + std::to_string(b) + " (id " + std::to_string(id[b]) + ")";
    if (first_element[b + 1] <= first_element[b])
      return which + " has no elements (first_element not increasing)";
    if (!is_clump[b] && first_element[b + 1] - first_element[b] != 1)
      return which + " is a ball of several elements";
    if (is_clump[b] > 1) return which + " has is_clump " + std::to_string(is_clump[b]);
    if (!material_ok(body_material[b]))
      return which + " has material index " + std::to_string(body_material[b]) + " of " +
             std::to_string(num_materials);
    if (!(x[b].allFinite() && v[b].allFinite() && w[b].allFinite() && L[b].allFinite() &&
          f[b].allFinite() && t[b].allFinite()))
      return which + " has a non-finite position, velocity, force or moment";
    if (!positive_finite(mass[b]) || !positive_finite(inertia[b].minCoeff()) ||
        !inertia[b].allFinite())
      return which + " has a mass or inertia that is not positive and finite";
    if (!unit_norm(q[b]))
      return which + " has an orientation quaternion of norm " + std::to_string(q[b].norm());
    if (id[b] < 0) return which + " has a negative id";
    for (int e = first_element[b]; e < first_element[b + 1]; ++e) {
      if (body[e] != static_cast<int>(b))
        return "element " + std::to_string(e) + " names body " + std::to_string(body[e]) +
               " but lies in the range of " + which;
      if (!material_ok(material[e]))
        return "element " + std::to_string(e) + " has material index " +
               std::to_string(material[e]) + " of " + std::to_string(num_materials);
      if (!positive_finite(radius[e]) || !offset[e].allFinite() || !pos[e].allFinite())
        return "element " + std::to_string(e) +
               " has a radius, offset or position that is "
               "not finite (or a radius not positive)";
    }
  }
  std::vector<std::int64_t> sorted = id;
  std::sort(sorted.begin(), sorted.end());
  const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
  if (twice != sorted.end()) return "id " + std::to_string(*twice) + " is given to two bodies";
  return "";
}

int Particles::add_body(const Vec3& centre, const Quat& orientation, double m, const Vec3& I,
                        int mat, bool clump, std::int64_t user_id) {
  if (first_element.empty()) first_element.push_back(0);
  x.push_back(centre);
  v.push_back(Vec3::Zero());
  q.push_back(orientation.normalized());
  w.push_back(Vec3::Zero());
  L.push_back(Vec3::Zero());
  f.push_back(Vec3::Zero());
  t.push_back(Vec3::Zero());
  mass.push_back(m);
  inertia.push_back(I);
  body_material.push_back(mat);
  id.push_back(user_id);
  is_clump.push_back(clump ? 1 : 0);
  return num_bodies() - 1;
}

int Particles::add_ball(const Vec3& centre, double r, int mat, double density,
                        std::int64_t user_id) {
  const double m = density * 4.0 / 3.0 * M_PI * r * r * r;
  return add_body_with_elements(centre, Quat::Identity(), m, Vec3::Constant(0.4 * m * r * r), mat,
                                false, user_id, {{Vec3::Zero(), r}});
}

int Particles::add_clump(const ClumpTemplate& tmpl, const Vec3& centre, const Quat& orientation,
                         int mat, double density, std::int64_t user_id) {
  return add_body_with_elements(centre, orientation, density * tmpl.volume,
                                density * tmpl.principal_moments, mat, true, user_id, tmpl.spheres);
}

int Particles::add_body_with_elements(const Vec3& centre, const Quat& orientation, double m,
                                      const Vec3& I, int mat, bool clump, std::int64_t user_id,
                                      const std::vector<SphereShape>& elements) {
  const int b = add_body(centre, orientation, m, I, mat, clump, user_id);
  const Mat3 R = q[b].toRotationMatrix();
  for (const auto& s : elements) {
    pos.push_back(centre + R * s.centre);
    offset.push_back(s.centre);
    radius.push_back(s.radius);
    body.push_back(b);
    material.push_back(mat);
  }
  first_element.push_back(num_elements());
  return b;
}

Particles Particles::subset(const std::vector<char>& keep) const {
  Particles out;
  for (int b = 0; b < num_bodies(); ++b) {
    if (!keep[b]) continue;
    std::vector<SphereShape> elements;
    for (int e = first_element[b]; e < first_element[b + 1]; ++e)
      elements.push_back({offset[e], radius[e]});
    const int k = out.add_body_with_elements(x[b], q[b], mass[b], inertia[b], body_material[b],
                                             is_clump[b], id[b], elements);
    out.v[k] = v[b], out.w[k] = w[b], out.L[k] = L[b];
    for (int e = first_element[b], o = out.first_element[k]; e < first_element[b + 1]; ++e, ++o)
      out.material[o] = material[e], out.pos[o] = pos[e];
  }
  return out;
}

namespace {

// Interleaves the bits of three 21-bit cell coordinates (Morton order).
std::uint64_t morton(std::uint64_t x, std::uint64_t y, std::uint64_t z) {
  auto spread = [](std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | spread(y) << 1 | spread(z) << 2;
}

template <class T>
void permute(std::vector<T>& v, const std::vector<int>& order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (int i : order) out.push_back(v[i]);
  v.swap(out);
}

}  // namespace

void Particles::sort_spatially(double cell) {
  const int nb = num_bodies();
  if (nb == 0) return;
  Vec3 lo = x[0];
  for (const auto& c : x) lo = lo.cwiseMin(c);
  std::vector<std::uint64_t> key(nb);
  for (int b = 0; b < nb; ++b) {
    const Vec3 c = (x[b] - lo) / cell;
    key[b] = morton(static_cast<std::uint64_t>(c.x()), static_cast<std::uint64_t>(c.y()),
                    static_cast<std::uint64_t>(c.z()));
  }
  std::vector<int> order(nb);
  for (int b = 0; b < nb; ++b) order[b] = b;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });

  std::vector<int> element_order;
  element_order.reserve(num_elements());
  std::vector<int> first{0};
  for (int b : order) {
    for (int e = first_element[b]; e < first_element[b + 1]; ++e) element_order.push_back(e);
    first.push_back(static_cast<int>(element_order.size()));
  }
  permute(x, order), permute(v, order), permute(q, order), permute(w, order), permute(L, order);
  permute(f, order), permute(t, order), permute(mass, order), permute(inertia, order);
  permute(body_material, order), permute(id, order), permute(is_clump, order);
  first_element.swap(first);
  permute(pos, element_order), permute(offset, element_order), permute(radius, element_order);
  permute(material, element_order);
  for (int b = 0; b < nb; ++b)
    for (int e = first_element[b]; e < first_element[b + 1]; ++e) body[e] = b;
}

void Particles::update_element_positions(bool parallel) {
  const int nb = num_bodies();
#pragma omp parallel for schedule(static) if (parallel)
  for (int b = 0; b < nb; ++b) update_body_elements(b);
}

void Particles::update_body_elements(int b) {
  const int e0 = first_element[b], e1 = first_element[b + 1];
  if (!is_clump[b]) {
    pos[e0] = x[b];
    return;
  }
  const Mat3 R = q[b].toRotationMatrix();
  for (int e = e0; e < e1; ++e) pos[e] = x[b] + R * offset[e];
}

Mat3 Particles::world_inertia(int b) const {
  const Mat3 R = q[b].toRotationMatrix();
  return R * inertia[b].asDiagonal() * R.transpose();
}

double Particles::kinetic_energy() const {
  double e = 0;
  for (int b = 0; b < num_bodies(); ++b) {
    e += 0.5 * mass[b] * v[b].squaredNorm();
    const Vec3 wb = q[b].conjugate() * w[b];  // body frame
    e += 0.5 * wb.dot(inertia[b].cwiseProduct(wb));
  }
  return e;
}

double Particles::bounding_radius(int b) const {
  double r = 0;
  for (int e = first_element[b]; e < first_element[b + 1]; ++e)
    r = std::max(r, offset[e].norm() + radius[e]);
  return r;
}

double Particles::max_element_radius() const {
  return radius.empty() ? 0.0 : *std::max_element(radius.begin(), radius.end());
}

}  // namespace trackbed::dem
