// Full-DEM reference of the breakable tunnel (docs/architecture.md,
// "Speed-versus-accuracy study"): the membrane servo's target forces reproduce
// the in-situ stress exactly; the servo holds it in a packed, bonded disk; bad
// parameters are refused.
#include <catch2/catch.hpp>

#include "coupling/full_dem_reference.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace demfem;
using dem::Vec;

namespace
{
  // A closed ring of n facets around the origin, radii perturbed (a
  // membrane after deformation is no longer a regular polygon).
  int ring(dem::Model<2> &m, int n, double R)
  {
    const int        w = m.walls.add_wall("membrane");
    std::vector<int> v(n);
    for (int k = 0; k < n; ++k)
      {
        const double th = 2 * M_PI * k / n, r = R * (1 + 0.05 * std::sin(3.0 * k));
        v[k] = m.walls.add_vertex(r * Vec<2>(std::cos(th), std::sin(th)));
      }
    for (int k = 0; k < n; ++k)
      m.walls.add_facet(w, {{v[k], v[(k + 1) % n]}});
    return w;
  }

  // The 2D elastic disk: a = 0.4 m, R = 8 a, a/d = 3 (about 1 900
  // grains), unbreakable bonds, -10/-20 MPa; output in the temporary
  // directory `name`.
  coupling::FullDemReferenceParams elastic_disk(const std::string &name)
  {
    coupling::FullDemReferenceParams p;
    p.output_directory = (std::filesystem::temp_directory_path() / name).string();
    std::filesystem::remove_all(p.output_directory);
    p.tunnel_radius    = 0.4;
    p.sigma0           = (Eigen::Matrix2d() << -10e6, 0, 0, -20e6).finished();
    p.region.radius    = 3.2;
    const double d     = 0.4 / 3;
    p.region.d_lo      = 0.8 * d;
    p.region.d_hi      = 1.2 * d;
    p.region.emod      = 20e9;
    p.region.lnm_emod  = 20e9;
    p.region.breakable = false;
    p.phase_step_limit = 8000;
    return p;
  }

  // The 3D tests' slab: a = 0.4 m, R = 5 a (the 8 a minimum lowered to keep
  // the tests cheap: about 2 300 spheres), a/d = 3, three grains thick,
  // -10/-20 MPa; output in the temporary directory `name`.
  coupling::FullDemReferenceParams slab_3d(const std::string &name)
  {
    coupling::FullDemReferenceParams p;
    p.dimension        = 3;
    p.output_directory = (std::filesystem::temp_directory_path() / name).string();
    std::filesystem::remove_all(p.output_directory);
    p.tunnel_radius         = 0.4;
    p.sigma0                = (Eigen::Matrix2d() << -10e6, 0, 0, -20e6).finished();
    p.min_radius_factor     = 5;
    p.region.radius         = 2.0;
    const double d          = 0.4 / 3;
    p.region.d_lo           = 0.8 * d;
    p.region.d_hi           = 1.2 * d;
    p.region.slab_thickness = 3 * d;
    p.region.emod           = 20e9;
    p.region.lnm_emod       = 20e9;
    p.phase_step_limit      = 8000;
    return p;
  }
} // namespace

TEST_CASE("full-DEM reference: membrane target forces carry sigma0 exactly",
          "[reference]")
{
  // Closed form: for a closed polygon, sum over edges of (sigma n_e) L_e (x)
  // (x_a + x_b)/2 = sigma A (divergence theorem, exact for straight edges),
  // so the half-edge lumped targets give back sigma0 to round-off, shear
  // included, whatever the polygon.
  dem::Model<2>         m;
  const int             w = ring(m, 48, 2.0);
  const Eigen::Matrix2d s0 =
      (Eigen::Matrix2d() << -20e6, 5e6, 5e6, -50e6).finished(); // with shear
  coupling::MembraneServo servo(m, w, coupling::MembraneServoParams(), 0.1, 4e10);
  servo.set_target(s0);
  const auto F = servo.target_forces(m, 1.0);
  REQUIRE(F.size() == 48);
  for (std::size_t j = 0; j < F.size(); ++j)
    m.walls.vertex_force[servo.vertices()[j]] = F[j];
  CHECK((servo.held_stress(m) - s0).norm() <= 1e-12 * s0.norm());
  CHECK(servo.relative_error(m, 1.0) <= 1e-12);
  // half the load: the error is the missing half
  CHECK(servo.relative_error(m, 0.5) == Approx(0.5).epsilon(1e-12));
  // compression pushes the vertices outward: F . x > 0 on average
  double push = 0;
  for (std::size_t j = 0; j < F.size(); ++j)
    push += F[j].dot(m.walls.vertex[servo.vertices()[j]]);
  CHECK(push > 0);
}

TEST_CASE("full-DEM reference: the servo holds the in-situ stress, elastic response",
          "[reference]")
{
  // a = 0.4 m, R = 8 a, a/d = 3 (about 1 900 grains), unbreakable bonds:
  // the membrane must hold sigma0 within its 2 % tolerance, and the grains'
  // own (Love-Weber) stress in r < R/2 must match it as well.
  const auto         p = elastic_disk("demfem_reference");
  std::ostringstream log;
  const auto         r = coupling::run_full_dem_reference(p, log);
  INFO(log.str());
  REQUIRE(!r.diverged);
  CHECK(r.equilibrated);
  CHECK(r.status == coupling::RunStatus::ok);
  CHECK(r.servo_held_insitu);
  CHECK(r.servo_error_insitu <= p.servo.tolerance);
  CHECK(r.servo_error_final <= p.servo.tolerance);
  // Independent check: the Love-Weber stress of the contacts in r < R/2.
  // Tolerance 5 %: the disk average truncates the contacts at its rim
  // (O(d/r) ~ 1 % here) and the packing is anisotropic at this coarse
  // resolution (measured 1.3 % at -20/-50 MPa, a/d = 4).
  const double e = (r.region_stress_insitu - p.sigma0).norm() / p.sigma0.norm();
  INFO("Love-Weber stress error " << e);
  CHECK(e <= 0.05);
  // Unbreakable: no cracks; the wall converges inward, of the Kirsch
  // magnitude a (S1 + S2) / (4 G) with the plane-strain constants of this
  // packing (E = 16.3 GPa, nu = 0.11, docs/tunnel.md); a/d = 3 is coarse
  // (the embedded study measured -21 % to +10 % over seeds at a/d = 3),
  // hence +-30 % (measured +15 %: 0.472 mm against 0.409 mm).
  CHECK(r.cracks_total == 0);
  const double G = 16.3e9 / (2 * 1.11), kirsch = 0.4 * 30e6 / (4 * G);
  INFO("wall convergence " << r.wall_convergence_mean << " m, Kirsch " << kirsch);
  CHECK(r.wall_convergence_mean == Approx(kirsch).epsilon(0.3));
  CHECK(std::filesystem::exists(p.output_directory + "/summary.json"));
  CHECK(std::filesystem::exists(p.output_directory + "/cracks.csv"));
}

TEST_CASE("full-DEM reference: summary.json says ok only when every phase ended at its "
          "tolerances",
          "[reference]")
{
  // The elastic disk of the test above, cut short: 300 steps after the
  // in-situ ramp cannot bring the unbalanced ratio of ~1 900 grains below
  // 1e-3 (the full run needs thousands), so the run is not_equilibrated;
  // with a servo tolerance of 1e-6 the membrane cannot hold sigma0 that
  // closely either, and in_situ_not_reached, the more severe, is reported.
  auto read_status = [](const std::string &dir) {
    std::ifstream     in(dir + "/summary.json");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  auto p             = elastic_disk("demfem_reference_status");
  p.phase_step_limit = 300;
  p.servo.tolerance  = 0.5; // held (the ramp ends at sigma0), not equilibrated
  std::ostringstream log;
  auto               r = coupling::run_full_dem_reference(p, log);
  INFO(log.str());
  REQUIRE(!r.diverged);
  CHECK(r.servo_held_insitu);
  CHECK(!r.equilibrated);
  CHECK(r.status == coupling::RunStatus::not_equilibrated);
  CHECK_THAT(read_status(p.output_directory),
             Catch::Contains("\"status\": \"not_equilibrated\""));

  p.servo.tolerance = 1e-6;
  r                 = coupling::run_full_dem_reference(p, log);
  REQUIRE(!r.diverged);
  CHECK(!r.servo_held_insitu);
  CHECK(r.status == coupling::RunStatus::in_situ_not_reached);
  CHECK_THAT(read_status(p.output_directory),
             Catch::Contains("\"status\": \"in_situ_not_reached\""));
}

TEST_CASE("full-DEM reference 3D: membrane target forces carry sigma0 exactly",
          "[reference]")
{
  // Closed form: over the lateral surface of the slab, sum over facets of
  // (sigma n_e A_e) (x) c_e = sigma V in the xy block (divergence theorem,
  // exact for plane triangles; the planes z = 0, t add nothing to it), so
  // the third-per-vertex lumped targets give back sigma0 to round-off,
  // shear included, on a membrane whose three vertex layers moved apart
  // in xy (a deformed membrane is no longer a prism).
  dem::Model<3> m;
  const double  R = 2.0, t = 0.6;
  const int     w = coupling::add_cylinder_ring(m.walls, R, t, 40, 3, "membrane");
  for (std::size_t v = 0; v < m.walls.vertex.size(); ++v)
    {
      auto        &x = m.walls.vertex[v];
      const double f = 1 + 0.05 * std::sin(3.0 * v) + 0.02 * x[2] / t;
      x[0] *= f;
      x[1] *= f;
    }
  const Eigen::Matrix2d   s0 = (Eigen::Matrix2d() << -20e6, 5e6, 5e6, -50e6).finished();
  coupling::MembraneServo servo(m, w, coupling::MembraneServoParams(), 0.1, 4e10);
  servo.set_target(s0);
  REQUIRE(servo.vertices().size() == 40 * 4);
  // The enclosed volume, against the shoelace area of the vertex layers:
  // the prism between two layers of vertices with chords in between has
  // volume h (A_lo + A_hi) / 2 only when the layers are similar; here the
  // check is the layer-independent one: a regular, unperturbed membrane.
  {
    dem::Model<3> reg;
    const int     wr = coupling::add_cylinder_ring(reg.walls, R, t, 40, 3, "membrane");
    coupling::MembraneServo sr(reg, wr, coupling::MembraneServoParams(), 0.1, 4e10);
    const double            polygon = 0.5 * 40 * R * R * std::sin(2 * M_PI / 40);
    CHECK(sr.enclosed(reg) == Approx(polygon * t).epsilon(1e-12));
  }
  const auto F = servo.target_forces(m, 1.0);
  REQUIRE(F.size() == servo.vertices().size());
  for (std::size_t j = 0; j < F.size(); ++j)
    {
      CHECK(F[j][2] == 0.0); // the membrane pushes in the xy plane only
      m.walls.vertex_force[servo.vertices()[j]] = F[j];
    }
  CHECK((servo.held_stress(m) - s0).norm() <= 1e-12 * s0.norm());
  CHECK(servo.relative_error(m, 1.0) <= 1e-12);
  CHECK(servo.relative_error(m, 0.5) == Approx(0.5).epsilon(1e-12));
}

TEST_CASE("full-DEM reference 3D: the servo holds the in-situ stress in a plane-strain "
          "slab, elastic response",
          "[reference]")
{
  // The slab of slab_3d between fixed frictionless walls, unbreakable
  // bonds: the membrane must hold
  // sigma0 within its 2 % tolerance, and the grains' own (Love-Weber)
  // stress in r < R/2 must match it.
  auto p             = slab_3d("demfem_reference_3d");
  p.region.breakable = false;
  std::ostringstream log;
  const auto         r = coupling::run_full_dem_reference(p, log);
  INFO(log.str());
  REQUIRE(!r.diverged);
  CHECK(r.equilibrated);
  CHECK(r.servo_held_insitu);
  CHECK(r.servo_error_final <= p.servo.tolerance);
  CHECK(r.slab_thickness == p.region.slab_thickness);
  // Love-Weber stress of the contacts in the cylinder r < R/2: 5 % as in
  // 2D (the cylinder truncates the contacts at its rim, O(d/r) ~ 3 % here
  // with R/2 = 7.5 d; measured 3.2 %).
  const double e = (r.region_stress_insitu - p.sigma0).norm() / p.sigma0.norm();
  INFO("Love-Weber stress error " << e);
  CHECK(e <= 0.05);
  // Unbreakable: no cracks; the wall converges inward. Closed form: the
  // excavation part of the Lame solution of the ring a < r < b under the
  // mean traction p = -(Sxx + Syy)/2 at b (the deviatoric part adds
  // cos 2 theta terms, zero on the mean), plane strain:
  //   u = (p a / E) (2 (1 - nu^2) b^2 / (b^2 - a^2) - (1 + nu)(1 - 2 nu)),
  // Kirsch's p a (1 + nu) / E as b -> oo (+7.5 % at b = 5 a). Constants of
  // a slab three grains thick (E = 12.5 GPa, nu = 0.10, docs/study.md "3D:
  // the slab and the section"); a/d = 3 is coarse and this packing more
  // porous (0.45), hence +-30 % as in 2D (measured +19 %: 0.675 mm against
  // 0.568 mm).
  CHECK(r.cracks_total == 0);
  const double E = 12.5e9, nu = 0.10, a = 0.4, b = 2.0, pm = 15e6;
  const double lame =
      pm * a / E *
      (2 * (1 - nu * nu) * b * b / (b * b - a * a) - (1 + nu) * (1 - 2 * nu));
  INFO("wall convergence " << r.wall_convergence_mean << " m, Lame " << lame);
  CHECK(r.wall_convergence_mean == Approx(lame).epsilon(0.3));
  CHECK(std::filesystem::exists(p.output_directory + "/cracks.csv"));
}

TEST_CASE("full-DEM reference 3D: breakable slab, the membrane's band stays intact, "
          "the excavation cracks the wall",
          "[reference]")
{
  // The elastic test's slab (R = 5 a, a/d = 3, three grains thick) with
  // breakable flat joints (tension 8 MPa, cohesion 40 MPa, as
  // apps/examples/tunnel_3d.prm) at -10/-20 MPa. Measured before the band
  // existed: 524 bonds broke at the in-situ stress, 535 cracks within two
  // grains of the membrane; with the band (3 grain diameters) 9 in-situ
  // cracks, none there, and 74 excavation cracks, zone depth 0.18 m.
  auto         p  = slab_3d("demfem_reference_3d_breakable");
  const double d  = p.region.mean_diameter();
  p.region.fj_ten = 8e6;
  p.region.fj_coh = 40e6;
  // Compared with the elastic zone of a 30 MPa crack-initiation stress, as
  // the embedded run is (coupling/initiation_zone.h; plane-strain sigma_zz
  // with nu 0.25: the far field's 12.5 MPa of differential stress is below).
  p.crack_initiation = {{"crack_initiation", 30e6}};
  p.poisson_ratio    = 0.25;
  std::ostringstream log;
  const auto         r = coupling::run_full_dem_reference(p, log);
  INFO(log.str());
  REQUIRE(!r.diverged);
  CHECK(r.equilibrated);
  CHECK(r.servo_held_insitu);
  // The band: its bonds counted, and no crack within two grains of the
  // membrane (all of that ring lies inside the unbreakable band of three).
  CHECK(r.unbreakable_band_bonds > 0);
  CHECK(r.cracks_near_boundary == 0);
  // The in-situ stress breaks a few weak bonds at most (measured 9 of
  // about 6 000); the excavation breaks many, near the wall: the zone
  // holds most of them and is between half a grain and R/2 deep.
  CHECK(r.cracks_before_excavation < 30);
  const std::size_t exc = r.cracks_total - r.cracks_before_excavation;
  CHECK(exc >= 20);
  CHECK(r.damage.connected_cracks >= exc / 2);
  CHECK(r.damage_zone_depth >= 0.5 * d);
  CHECK(r.damage_zone_depth <= 0.5 * p.region.radius - p.tunnel_radius);
  REQUIRE(r.initiation_zones.size() == 1);
  const auto &z = r.initiation_zones[0];
  CHECK(z.cracks == r.damage.cracks);
  CHECK(z.zone_cracks == r.damage.connected_cracks);
  CHECK(!z.far_field_exceeds);
  CHECK(z.depth ==
        Approx(coupling::kirsch::damage_radius(p.sigma0, p.tunnel_radius, 30e6, 0.25) -
               p.tunnel_radius)
            .epsilon(1e-12));
  CHECK(z.cracks_inside <= z.cracks_near);
  // cracks.csv has the z column in 3D
  std::ifstream in(p.output_directory + "/cracks.csv");
  std::string   header;
  std::getline(in, header);
  CHECK(header.rfind("x,y,z,distance_from_wall,", 0) == 0);
}

TEST_CASE("full-DEM reference: bad parameters are refused before any output",
          "[reference]")
{
  coupling::FullDemReferenceParams p;
  p.output_directory =
      (std::filesystem::temp_directory_path() / "demfem_reference_bad").string();
  std::filesystem::remove_all(p.output_directory);
  p.tunnel_radius = 1.0;
  p.region.radius = 6.0; // < 8 a
  std::ostringstream log;
  CHECK_THROWS_WITH(coupling::run_full_dem_reference(p, log),
                    Catch::Contains("at least 8 x Tunnel/radius"));
  p.region.radius = 8.0;
  p.sigma0.setZero();
  CHECK_THROWS_WITH(coupling::run_full_dem_reference(p, log),
                    Catch::Contains("in situ stress"));
  p.sigma0    = (Eigen::Matrix2d() << -10e6, 0, 0, -20e6).finished();
  p.dimension = 4;
  CHECK_THROWS_WITH(coupling::run_full_dem_reference(p, log),
                    Catch::Contains("Problem/dimension must be 2 or 3"));
  p.dimension     = 2;
  p.boundary_band = 1e3; // wider than R / 4
  CHECK_THROWS_WITH(coupling::run_full_dem_reference(p, log),
                    Catch::Contains("reference boundary band"));
  p.boundary_band    = 3;
  p.crack_initiation = {{"crack_initiation", -1.0}};
  CHECK_THROWS_WITH(coupling::run_full_dem_reference(p, log),
                    Catch::Contains("material file's crack_initiation"));
  p.crack_initiation.clear();
  p.dimension             = 3; // a slab needs its thickness
  p.region.slab_thickness = 0;
  CHECK_THROWS_WITH(coupling::run_full_dem_reference(p, log),
                    Catch::Contains("slab thickness"));
  CHECK(!std::filesystem::exists(p.output_directory));
}
