#pragma once
// Fixtures shared by the Voronoi tests (tests/voronoi): the lab tests'
// genesis specimen, packed once per test executable, and the grain
// elasticity of the flexible-grain tests.
#include "dem/voronoi/flexible_grain.h"
#include "dem/voronoi/voronoi_lab_test.h"

#include <cstdint>
#include <random>
#include <vector>

namespace demfem::dem::voronoi::testing
{
  /// The genesis specimen of the lab tests (~200 grains, 25 x 50 mm).
  inline const VoronoiSpecimen &lab_specimen()
  {
    static const VoronoiSpecimen s = [] {
      VoronoiSpecimenParams p;
      p.width    = 0.025;
      p.height   = 0.05;
      p.n_grains = 200;
      return make_voronoi_specimen(p);
    }();
    return s;
  }

  /// Grains of modulus E (plane strain), nu = 0.2, rho = 2650 kg/m^3.
  inline GrainElasticity grain_elasticity(double E, double thickness = 1)
  {
    GrainElasticity g;
    g.youngs_modulus = E;
    g.poisson_ratio  = 0.2;
    g.density        = 2650;
    g.thickness      = thickness;
    return g;
  }

  /// Jittered hexagonal lattice of polydisperse disks: nx x ny disks at
  /// spacing h, centres moved by up to `jitter` h in x and y, radii in
  /// [0.4, 0.5] h; [0, W] x [0, H] is the lattice's rectangle.
  struct Packing
  {
    std::vector<double> x, y, r;
    double              W = 0, H = 0;
  };
  inline Packing jittered(int nx, int ny, std::uint64_t seed, double jitter = 0.12,
                          double h = 1e-3)
  {
    std::mt19937_64                        rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Packing                                p;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        {
          p.x.push_back((i + 0.5 + 0.5 * (j % 2)) * h + jitter * h * u(rng));
          p.y.push_back((j + 0.5) * 0.866 * h + jitter * h * u(rng));
          p.r.push_back(0.45 * h + 0.05 * h * u(rng));
        }
    p.W = (nx + 0.5) * h;
    p.H = ny * 0.866 * h;
    return p;
  }
} // namespace demfem::dem::voronoi::testing
