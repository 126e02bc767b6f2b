#include "dem/samples/porosity.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/input_error.h"

namespace trackbed::dem {

PorosityMeasure porosity_in_box(const Particles& p, const Vec3& lower, const Vec3& upper,
                                double spacing) {
  return porosity_in_region(p, lower, upper, spacing, nullptr);
}

PorosityMeasure porosity_in_region(const Particles& p, const Vec3& lower, const Vec3& upper,
                                   double spacing, const std::function<bool(const Vec3&)>& inside) {
  const Vec3 size = upper - lower;
  if (!(size.minCoeff() > 0) || !(spacing > 0)) {
    std::ostringstream s;
    s << "porosity: measuring box " << lower.transpose() << " to " << upper.transpose()
      << " with spacing " << spacing << " m; valid: upper > lower and a spacing > 0";
    throw InputError(s.str());
  }
  int n[3];
  double count = 1;
  for (int k = 0; k < 3; ++k) {
    n[k] = std::max(1, static_cast<int>(std::lround(size[k] / spacing)));
    count *= n[k];
  }
  if (count > 2147483647.0)
    throw InputError(
        "porosity: the measuring grid would have more than 2^31 points; valid: a "
        "larger spacing");
  const Vec3 h(size.x() / n[0], size.y() / n[1], size.z() / n[2]);
  std::vector<unsigned char> solid(static_cast<std::size_t>(count), 0);
  for (int e = 0; e < p.num_elements(); ++e) {
    const Vec3 c = p.pos[e];
    const double r = p.radius[e];
    int lo[3], hi[3];
    bool outside = false;
    for (int k = 0; k < 3; ++k) {
      // Point i sits at lower + (i + 1/2) h.
      lo[k] = std::max(0, static_cast<int>(std::ceil((c[k] - r - lower[k]) / h[k] - 0.5)));
      hi[k] = std::min(n[k] - 1, static_cast<int>(std::floor((c[k] + r - lower[k]) / h[k] - 0.5)));
      outside |= lo[k] > hi[k];
    }
    if (outside) continue;
    const double r2 = r * r;
    for (int iz = lo[2]; iz <= hi[2]; ++iz) {
      const double dz = lower.z() + (iz + 0.5) * h.z() - c.z();
      for (int iy = lo[1]; iy <= hi[1]; ++iy) {
        const double dy = lower.y() + (iy + 0.5) * h.y() - c.y();
        const double left = r2 - dz * dz - dy * dy;
        if (left < 0) continue;
        // The run of x points inside the sphere on this line.
        const double half = std::sqrt(left);
        const int x0 =
            std::max(lo[0], static_cast<int>(std::ceil((c.x() - half - lower.x()) / h.x() - 0.5)));
        const int x1 =
            std::min(hi[0], static_cast<int>(std::floor((c.x() + half - lower.x()) / h.x() - 0.5)));
        const std::size_t row = (static_cast<std::size_t>(iz) * n[1] + iy) * n[0];
        for (int ix = x0; ix <= x1; ++ix) solid[row + ix] = 1;
      }
    }
  }
  long filled = 0, points = 0;
  for (int iz = 0; iz < n[2]; ++iz)
    for (int iy = 0; iy < n[1]; ++iy)
      for (int ix = 0; ix < n[0]; ++ix) {
        if (inside &&
            !inside(lower + Vec3((ix + 0.5) * h.x(), (iy + 0.5) * h.y(), (iz + 0.5) * h.z())))
          continue;
        ++points;
        filled += solid[(static_cast<std::size_t>(iz) * n[1] + iy) * n[0] + ix];
      }
  if (points == 0) throw InputError("porosity: no measuring point lies in the region");
  return {1.0 - static_cast<double>(filled) / points, points * h.prod(), points};
}

}  // namespace trackbed::dem
