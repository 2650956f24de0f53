// Flat-joint element geometry table (see flat_joint_elements.h).
#include "dem/laws/flat_joint_elements.h"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>

namespace demfem::dem
{
  const double *flat_joint_unit_geometry(int Nr, int Nal)
  {
    static std::mutex                                               mutex;
    static std::map<std::pair<int, int>, std::unique_ptr<double[]>> table;
    std::lock_guard<std::mutex>                                     lock(mutex);
    auto                                                           &t = table[{Nr, Nal}];
    if (!t)
      {
        const int ne = Nr * Nal;
        t.reset(new double[4 * std::size_t(ne)]);
        const double dr = 1.0 / Nr, da = 2 * M_PI / Nal;
        for (int e = 0; e < ne; ++e)
          {
            const int    I = e / Nal, J = e - I * Nal;
            const double r1 = I * dr, r2 = (I + 1) * dr;
            const double a1 = J * da, a2 = (J + 1) * da;
            const double radial = (r2 * r2 * r2 - r1 * r1 * r1) / (r2 * r2 - r1 * r1);
            t[e]                = 0.5 * (a2 - a1) * (r2 * r2 - r1 * r1);
            t[ne + e] = 2.0 / 3.0 * (std::sin(a2) - std::sin(a1)) / (a2 - a1) * radial;
            t[2 * ne + e] =
                2.0 / 3.0 * (std::cos(a1) - std::cos(a2)) / (a2 - a1) * radial;
            t[3 * ne + e] = 1.0 / t[e];
          }
      }
    return t.get();
  }
} // namespace demfem::dem
