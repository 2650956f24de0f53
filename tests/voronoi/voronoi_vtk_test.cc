// VTK output of rigid Voronoi grains (dem/voronoi/voronoi_vtk.h): the files
// parse back with VTK's reader, the counts and arrays match the model, and
// the grains' Love-Weber stress averages to the applied pressure.
#include "dem/voronoi/voronoi_lab_test.h"
#include "dem/voronoi/voronoi_vtk.h"

#include <catch2/catch.hpp>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <random>

using namespace demfem::dem;
using namespace demfem::dem::voronoi;

namespace
{
  /// Jittered hexagonal lattice as a specimen (no genesis: fast).
  VoronoiSpecimen lattice(int nx, int ny, std::uint64_t seed)
  {
    const double                           h = 1e-3;
    std::mt19937_64                        rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    VoronoiSpecimen                        s;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        {
          s.x.push_back((i + 0.5 + 0.5 * (j % 2)) * h + 0.12 * h * u(rng));
          s.y.push_back((j + 0.5) * 0.866 * h + 0.12 * h * u(rng));
          s.radius.push_back(0.45 * h + 0.05 * h * u(rng));
        }
    s.domain       = ClipDomain::rectangle(0, 0, (nx + 0.5) * h, ny * 0.866 * h);
    s.tessellation = laguerre_tessellation(s.x, s.y, s.radius, s.domain);
    return s;
  }

  ContactMaterial material()
  {
    ContactMaterial m;
    m.contact_modulus  = 50e9;
    m.kratio           = 1.5;
    m.tensile_strength = 10e6;
    m.cohesion         = 30e6;
    m.friction         = 0.5;
    m.thickness        = 0.01;
    return m;
  }

  vtkSmartPointer<vtkPolyData> read(const std::string &path)
  {
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    vtkSmartPointer<vtkPolyData> d = r->GetOutput();
    return d;
  }
} // namespace

TEST_CASE("Voronoi VTK: cells, points and cracks of a broken specimen parse back",
          "[voronoi][vtk]")
{
  const auto       spec = lattice(10, 14, 3);
  VoronoiLabParams p;
  p.test         = VoronoiTest::direct_tension;
  p.strain_limit = 2e-3;
  std::optional<RigidVoronoiModel> end;
  const auto r = run_voronoi_lab_test(spec, material(), 2650, p, &end);
  REQUIRE(end.has_value());
  const RigidVoronoiModel &m = *end;
  REQUIRE(r.cracks_tensile + r.cracks_shear > 0);

  const auto dir = std::filesystem::temp_directory_path() / "demfem_voronoi_vtk_test";
  std::filesystem::create_directories(dir);
  const std::string cells  = (dir / "cells.vtp").string(),
                    points = (dir / "points.vtp").string(),
                    cracks = (dir / "cracks.vtp").string();
  write_voronoi_cells_vtk(cells, spec.tessellation, m);
  write_voronoi_points_vtk(points, m);
  const int n_cracks = write_voronoi_cracks_vtk(cracks, m);
  CHECK(!std::filesystem::exists(cells + ".tmp")); // renamed

  const auto c      = read(cells);
  int        grains = 0, vertices = 0;
  for (int g = 0; g < m.n_grains(); ++g)
    if (!m.held[g])
      {
        ++grains;
        vertices += spec.tessellation.end(g) - spec.tessellation.begin(g);
      }
  CHECK(c->GetNumberOfCells() == grains);
  CHECK(c->GetNumberOfPoints() == vertices);
  for (const char *a : {"grain", "displacement", "rotation", "stress"})
    CHECK(c->GetCellData()->GetArray(a) != nullptr);

  const auto q = read(points);
  CHECK(q->GetNumberOfPoints() == m.contacts.n_points());
  CHECK(q->GetNumberOfVerts() == m.contacts.n_points());
  int tensile = 0, shear = 0;
  for (vtkIdType i = 0; i < q->GetNumberOfPoints(); ++i)
    {
      const int k = static_cast<int>(q->GetPointData()->GetArray("crack")->GetTuple1(i));
      tensile += k == 1;
      shear += k == 2;
      CHECK(q->GetPointData()->GetArray("damage_t")->GetTuple1(i) ==
            m.contacts.damage_t[i]);
    }
  CHECK(tensile == r.cracks_tensile);
  CHECK(shear == r.cracks_shear);

  const auto k = read(cracks);
  CHECK(n_cracks == r.cracks_tensile + r.cracks_shear);
  CHECK(k->GetNumberOfLines() == n_cracks);
  CHECK(k->GetNumberOfPoints() == 2 * n_cracks);
  // The pieces of a contact's cracked points tile its edge: each piece is a
  // sixth (ends) or two thirds (middle) of the edge length.
  double total = 0;
  for (vtkIdType i = 0; i < k->GetNumberOfLines(); ++i)
    {
      double a[3], b[3];
      k->GetPoint(2 * i, a);
      k->GetPoint(2 * i + 1, b);
      total += std::hypot(b[0] - a[0], b[1] - a[1]);
    }
  double expected = 0; // the same from the model: area / thickness
  for (int i = 0; i < m.contacts.n_points(); ++i)
    if (m.contacts.crack[i] == PointCrack::tensile ||
        m.contacts.crack[i] == PointCrack::shear)
      expected += m.contacts.area[i] / m.contacts.thickness();
  CHECK(total == Approx(expected).epsilon(1e-9));
  std::filesystem::remove_all(dir);
}

TEST_CASE("Voronoi grain stress: the Love-Weber average is the applied pressure",
          "[voronoi][vtk]")
{
  // In static equilibrium the volume average of the grain stresses is the
  // boundary average sum x (x) f / V = -P I (the contact forces cancel in
  // pairs at the same point). 4000 damped steps leave ~1e-4 of unbalance.
  const auto        spec = lattice(10, 12, 5);
  RigidVoronoiModel m(spec.tessellation, spec.x, spec.y, spec.radius, 2650, material());
  const double      P = 5e6;
  for (Side s : {Side::bottom, Side::right, Side::top, Side::left})
    m.set_pressure(s, P);
  const double dt = m.stable_time_step(0.5);
  for (int s = 0; s < 4000; ++s)
    m.step(dt);
  std::vector<double> sxx, syy, sxy;
  voronoi_grain_stress(spec.tessellation, m, sxx, syy, sxy);
  double mxx = 0, myy = 0, mxy = 0, A = 0;
  for (int g = 0; g < m.n_grains(); ++g)
    {
      const double a = spec.tessellation.area[g];
      mxx += a * sxx[g], myy += a * syy[g], mxy += a * sxy[g], A += a;
    }
  mxx /= A, myy /= A, mxy /= A;
  INFO("mean stress " << mxx << ", " << myy << ", " << mxy << " Pa");
  CHECK(mxx == Approx(-P).epsilon(1e-3));
  CHECK(myy == Approx(-P).epsilon(1e-3));
  CHECK(std::abs(mxy) < 1e-3 * P);
}

TEST_CASE("Voronoi VTK of flexible grains: triangles, points and cracks parse back, "
          "a uniform strain gives the closed-form Cauchy stress",
          "[voronoi][vtk][flexible]")
{
  const auto      spec = lattice(8, 10, 3);
  GrainElasticity g;
  g.youngs_modulus = 50e9;
  g.poisson_ratio  = 0.25;
  g.density        = 2650;
  g.thickness      = 0.01;
  VoronoiLabParams p;
  p.test         = VoronoiTest::direct_tension;
  p.strain_limit = 1e-3;
  std::optional<FlexibleVoronoiModel> end;
  const auto r = run_flexible_voronoi_lab_test(spec, material(), g, p, &end);
  REQUIRE(end.has_value());
  FlexibleVoronoiModel &m = *end;
  REQUIRE(r.cracks_tensile + r.cracks_shear > 0);

  const auto dir = std::filesystem::temp_directory_path() / "demfem_voronoi_vtk_flex";
  std::filesystem::create_directories(dir);
  const std::string cells  = (dir / "cells.vtp").string(),
                    points = (dir / "points.vtp").string(),
                    cracks = (dir / "cracks.vtp").string();
  write_voronoi_cells_vtk(cells, m);
  write_voronoi_points_vtk(points, m);
  const int  n_cracks = write_voronoi_cracks_vtk(cracks, m);
  const auto c        = read(cells);
  CHECK(c->GetNumberOfCells() == m.mesh.n_triangles());
  CHECK(c->GetNumberOfPoints() == m.mesh.n_nodes());
  for (const char *a : {"grain", "stress", "mean_stress"})
    CHECK(c->GetCellData()->GetArray(a) != nullptr);
  CHECK(c->GetPointData()->GetArray("displacement") != nullptr);
  const auto q = read(points);
  CHECK(q->GetNumberOfPoints() == m.contacts.n_points());
  const auto k = read(cracks);
  CHECK(n_cracks == r.cracks_tensile + r.cracks_shear);
  CHECK(k->GetNumberOfLines() == n_cracks);

  // x = F X (stretch, shear and a rotation of 0.3 rad): every triangle has
  // sigma = F S F^T / det F with S = lambda tr(E) I + 2 mu E, E = (F^T F -
  // I) / 2, and s_zz = lambda tr(E) / det F.
  const double c3 = std::cos(0.3), s3 = std::sin(0.3);
  const double U[4] = {1 + 2e-3, 5e-4, 5e-4, 1 - 1e-3}; // symmetric stretch
  const double F[4] = {c3 * U[0] - s3 * U[2], c3 * U[1] - s3 * U[3],
                       s3 * U[0] + c3 * U[2], s3 * U[1] + c3 * U[3]};
  for (int a = 0; a < m.mesh.n_nodes(); ++a)
    {
      m.x[a] = F[0] * m.mesh.x0[a] + F[1] * m.mesh.y0[a];
      m.y[a] = F[2] * m.mesh.x0[a] + F[3] * m.mesh.y0[a];
    }
  const double lam = g.lame_lambda(), mu = g.shear_modulus();
  const double Exx  = 0.5 * (F[0] * F[0] + F[2] * F[2] - 1);
  const double Eyy  = 0.5 * (F[1] * F[1] + F[3] * F[3] - 1);
  const double Exy  = 0.5 * (F[0] * F[1] + F[2] * F[3]);
  const double S[3] = {lam * (Exx + Eyy) + 2 * mu * Exx, lam * (Exx + Eyy) + 2 * mu * Eyy,
                       2 * mu * Exy};
  const double J    = F[0] * F[3] - F[1] * F[2];
  // (F S F^T)_ij = F_iK S_KL F_jL.
  auto sigma = [&](int i, int j) {
    const double SK[2][2] = {{S[0], S[2]}, {S[2], S[1]}};
    double       v        = 0;
    for (int K = 0; K < 2; ++K)
      for (int L = 0; L < 2; ++L)
        v += F[2 * i + K] * SK[K][L] * F[2 * j + L];
    return v / J;
  };
  const double sxx = sigma(0, 0), syy = sigma(1, 1), sxy = sigma(0, 1);
  const double szz = lam * (Exx + Eyy) / J;
  write_voronoi_cells_vtk(cells, m);
  const auto u = read(cells);
  // Roundoff: positions carry eps X (1e-2 m) against strains 1e-3 over
  // element heights >= 1e-5 m: 1e-8 relative to the stress scale; 1e-6.
  const double scale = std::max({std::abs(sxx), std::abs(syy), std::abs(sxy)});
  auto        *st    = u->GetCellData()->GetArray("stress");
  auto        *ms    = u->GetCellData()->GetArray("mean_stress");
  REQUIRE(u->GetNumberOfCells() == m.mesh.n_triangles());
  int bad = 0;
  for (vtkIdType e = 0; e < u->GetNumberOfCells(); ++e)
    {
      const double *v = st->GetTuple3(e);
      bad += std::abs(v[0] - sxx) > 1e-6 * scale || std::abs(v[1] - syy) > 1e-6 * scale ||
             std::abs(v[2] - sxy) > 1e-6 * scale ||
             std::abs(ms->GetTuple1(e) - (sxx + syy + szz) / 3) > 1e-6 * scale;
    }
  INFO("sigma " << sxx << ", " << syy << ", " << sxy << ", zz " << szz << " Pa");
  CHECK(bad == 0);
  // A rotation of 0.3 rad turns the stress: sigma_xy is far from the
  // unrotated S_xy (the test sees the push-forward, not S).
  CHECK(std::abs(sxy - S[2]) > 0.1 * scale);
  std::filesystem::remove_all(dir);
}
