// Per-grain averaged stress (dem/measure/particle_stress.h), as written to the particles VTK.
#include "dem/laws/linear_law.h"
#include "dem/engine/model.h"
#include "dem/measure/particle_stress.h"
#include "dem/io/vtk_output.h"

#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <catch2/catch.hpp>

#include <filesystem>
#include <random>

using namespace demfem::dem;

TEST_CASE("grain stress of a disk squeezed between two neighbours is -2F/(pi R) along "
          "the load",
          "[engine][stress]")
{
  // Three equal disks on the x axis, each neighbour overlapping the middle
  // one by delta: the middle disk carries F = kn delta at contact points
  // (R - delta/2) from its centre, so sigma_xx = -2 (R - delta/2) F / (pi R^2)
  // (unit thickness), sigma_yy = sigma_xy = 0 (closed form of the sum).
  Model<2>     m;
  const double R = 0.01, delta = 1e-4, kn = 1e8;
  m.particles.add(Vec<2>(-(2 * R - delta), 0), R, 2650);
  m.particles.add(Vec<2>(0, 0), R, 2650);
  m.particles.add(Vec<2>(2 * R - delta, 0), R, 2650);
  for (std::size_t i = 0; i < 3; ++i)
    m.particles.fixity[i] = fix_all; // forces computed, nothing moves
  LinearLaw<2>::Params lp;
  lp.kn = kn, lp.ks = kn;
  m.set_default_law(m.add_law<LinearLaw<2>>(lp), -1);
  m.set_timestep(1e-7);
  m.step();
  const auto   s     = grain_stresses(m);
  const double F     = kn * delta;
  const double exact = -2 * (R - delta / 2) * F / (M_PI * R * R);
  // Linear contact point is the overlap midpoint: exact to round-off.
  CHECK(s[1](0, 0) == Approx(exact).epsilon(1e-12));
  CHECK(std::abs(s[1](1, 1)) < 1e-9 * std::abs(exact));
  CHECK(std::abs(s[1](0, 1)) < 1e-9 * std::abs(exact));
  // The end disks have one contact each: half the middle one's stress.
  CHECK(s[0](0, 0) == Approx(exact / 2).epsilon(1e-12));
  // The solid fraction scales the tensor linearly.
  CHECK(grain_stresses(m, 0.8)[1](0, 0) == Approx(0.8 * exact).epsilon(1e-12));
  CHECK_THROWS_AS(grain_stresses(m, 0.0), InputError);
}

TEST_CASE("grain stresses sum to the branch-vector stress of the assembly",
          "[engine][stress]")
{
  // Volume-weighted sum over grains of sigma_p = sum over contacts of
  // sym((x1 - x2) (x) F_c) (F_c on piece 2): an identity, so round-off only.
  Model<3>        m;
  std::mt19937_64 g(7);
  auto            u = [&](double a, double b) {
    return a + (b - a) * (static_cast<double>(g() >> 11) * 0x1.0p-53);
  };
  for (int i = 0; i < 300; ++i)
    {
      m.particles.add(Vec<3>(u(0, 6), u(0, 6), u(0, 6)), u(0.4, 0.7), 2650);
      m.particles.fixity.back() = fix_all;
    }
  LinearLaw<3>::Params lp;
  lp.kn = 1e6, lp.ks = 5e5;
  m.set_default_law(m.add_law<LinearLaw<3>>(lp), -1);
  m.set_timestep(1e-6);
  m.step();
  const auto      s   = grain_stresses(m);
  StressTensor<3> sum = StressTensor<3>::Zero(), ref = StressTensor<3>::Zero();
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    {
      const double r = m.particles.radius[i];
      sum += (4.0 / 3.0 * M_PI * r * r * r) * s[i];
    }
  for (int k = 0; k < m.n_groups(); ++k)
    {
      const auto &grp = m.group(k);
      for (std::size_t c = 0; c < grp.size(); ++c)
        {
          const Vec<3> b = m.particles.x[grp.end1[c]] - m.particles.x[grp.end2[c]];
          const StressTensor<3> t = b * grp.force[c].transpose();
          ref += 0.5 * (t + t.transpose());
        }
    }
  REQUIRE(ref.norm() > 0); // the cloud overlaps: there are forces
  CHECK((sum - ref).norm() < 1e-10 * ref.norm());
}

TEST_CASE("particles VTK carries the averaged stress tensor", "[engine][stress][vtk]")
{
  Model<2>     m;
  const double R = 0.01, delta = 1e-4;
  m.particles.add(Vec<2>(-(R - delta / 2), 0), R, 2650);
  m.particles.add(Vec<2>(R - delta / 2, 0), R, 2650);
  m.particles.fixity[0] = m.particles.fixity[1] = fix_all;
  LinearLaw<2>::Params lp;
  lp.kn = 1e8, lp.ks = 1e8;
  m.set_default_law(m.add_law<LinearLaw<2>>(lp), -1);
  m.set_timestep(1e-7);
  m.step();
  const std::string path =
      (std::filesystem::temp_directory_path() / "demfem_stress_test.vtp").string();
  vtkout::write_particles(path, m, 0.75);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkDataArray *a = reader->GetOutput()->GetPointData()->GetArray("averaged_stress");
  REQUIRE(a != nullptr);
  REQUIRE(a->GetNumberOfComponents() == 9);
  const auto s = grain_stresses(m, 0.75);
  for (vtkIdType i = 0; i < 2; ++i)
    {
      CHECK(a->GetComponent(i, 0) == Approx(s[i](0, 0)).epsilon(1e-14));
      CHECK(a->GetComponent(i, 0) < 0);  // compression
      CHECK(a->GetComponent(i, 8) == 0); // plane: no zz entry
    }
  std::filesystem::remove(path);
}
