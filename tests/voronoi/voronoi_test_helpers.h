#pragma once
// Fixtures shared by the Voronoi tests (tests/voronoi): the lab tests'
// genesis specimen, packed once per test executable, the grain elasticity
// of the flexible-grain tests, and the packings of the new-contact tests
// (flexible and rigid grains).
#include "dem/voronoi/flexible_grain.h"
#include "dem/voronoi/tessellation.h"
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

  /// Elastic point contacts of the small-lattice tests: kn = 1e13 N/m^3,
  /// kappa = 2, mu = 0.5, t = 0.01 m; strengths of 1e12 Pa keep the
  /// installed contacts elastic.
  inline ContactMaterial elastic_lattice_contacts()
  {
    ContactMaterial m;
    m.kn               = 1e13;
    m.kratio           = 2;
    m.tensile_strength = 1e12;
    m.cohesion         = 1e12;
    m.friction         = 0.5;
    m.thickness        = 0.01;
    return m.brittle();
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

  /// One tessellation holding the cells of two tessellations side by side
  /// (no shared edge: the grains start without a contact).
  inline Tessellation concatenate(const Tessellation &t1, const Tessellation &t2)
  {
    Tessellation t  = t1;
    const int    n1 = t1.n_cells(), v1 = static_cast<int>(t1.vertex_x.size());
    t.area.insert(t.area.end(), t2.area.begin(), t2.area.end());
    t.centroid_x.insert(t.centroid_x.end(), t2.centroid_x.begin(), t2.centroid_x.end());
    t.centroid_y.insert(t.centroid_y.end(), t2.centroid_y.begin(), t2.centroid_y.end());
    t.empty_reason.insert(t.empty_reason.end(), t2.empty_reason.begin(),
                          t2.empty_reason.end());
    for (std::size_t c = 1; c < t2.offset.size(); ++c)
      t.offset.push_back(t2.offset[c] + v1);
    t.vertex_x.insert(t.vertex_x.end(), t2.vertex_x.begin(), t2.vertex_x.end());
    t.vertex_y.insert(t.vertex_y.end(), t2.vertex_y.begin(), t2.vertex_y.end());
    t.edge_length.insert(t.edge_length.end(), t2.edge_length.begin(),
                         t2.edge_length.end());
    for (int d : t2.edge_neighbour)
      t.edge_neighbour.push_back(d == Tessellation::boundary ? d : d + n1);
    for (int c : t2.empty_cells)
      t.empty_cells.push_back(c + n1);
    return t;
  }

  /// Jittered square lattice (12 x 12, spacing h = 1 mm, jitter 0.05 h) of
  /// disks of radius 0.7 h: the diagonal pairs that do not share a cell edge
  /// are 1.41 h +- the jitter apart against 1.4 h.
  struct SquareLattice
  {
    double              h = 1e-3;
    std::vector<double> x, y, r;
    Tessellation        tess;
  };
  inline SquareLattice square_lattice()
  {
    SquareLattice                          l;
    std::mt19937_64                        rng(8);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 12; ++i)
        {
          l.x.push_back((i + 0.5) * l.h + 0.05 * l.h * u(rng));
          l.y.push_back((j + 0.5) * l.h + 0.05 * l.h * u(rng));
          l.r.push_back(0.7 * l.h);
        }
    l.tess = laguerre_tessellation(l.x, l.y, l.r,
                                   ClipDomain::rectangle(0, 0, 12 * l.h, 12 * l.h));
    return l;
  }

  /// Grain A: disk R = 1 mm at (0, 0) in the square cell [-R, R]^2 (edges 2R);
  /// grain B: disk 0.8 R at (xb, 0) in the square cell of half-width 0.8 R
  /// (edges 1.6 R). The facing edges meet when the disks touch.
  struct TwoGrains
  {
    std::vector<double> x, y, r;
    Tessellation        tess;
  };
  inline TwoGrains two_separate_grains(double xb, double yb = 0)
  {
    constexpr double R = 1e-3;
    TwoGrains        g;
    g.x             = {0, xb};
    g.y             = {0, yb};
    g.r             = {R, 0.8 * R};
    const double rb = 0.8 * R;
    const auto   ta =
        laguerre_tessellation({0.0}, {0.0}, {R}, ClipDomain::rectangle(-R, -R, R, R));
    const auto tb = laguerre_tessellation(
        {xb}, {yb}, {rb}, ClipDomain::rectangle(xb - rb, yb - rb, xb + rb, yb + rb));
    g.tess = concatenate(ta, tb);
    return g;
  }
} // namespace demfem::dem::voronoi::testing
