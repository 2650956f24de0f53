// A tunnel section in a 3D continuum (docs/architecture.md, "In-situ stress and
// excavation"): the DEM section (r < b, 0 <= z <= t) is surrounded by continuum
// on every side — beyond its rim and, over Continuum/axial extension L, beyond
// both ends — with the tunnel through the whole length (coupled_model.h,
// fem::generate_section_mesh). The mesh, the force balance across the whole
// interface (rim and ends), the embedded patch test (incl. szz carried through
// the ends) and the excavation convergence vs plane-strain Kirsch (exact for a
// tunnel excavated along its whole length between rollers), the app run with
// its VTK read back, and bad input.
#include <catch2/catch.hpp>

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include "coupling/coupled_model.h"
#include "coupling/slaved_layer_model.h"
#include "coupling/tunnel_run.h"
#include "fem/mesh.h"
#include "helpers.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

using namespace demfem;
using namespace demfem::coupling;
using demfem::test::read_file;

namespace
{
  RegionParams section_region(double b, double d_lo, double d_hi, double t)
  {
    return test::slab_region(b, d_lo, d_hi, t);
  }

  ContinuumParams section_continuum(double E, double nu, double R, double L, double a)
  {
    ContinuumParams c;
    c.young_modulus   = E;
    c.poisson_ratio   = nu;
    c.outer_radius    = R;
    c.axial_extension = L;
    c.tunnel_radius   = a;
    return c;
  }

  void cycle(CoupledModel<3> &m, int ramp, int total)
  {
    for (int n = 0; n < total; ++n)
      {
        m.set_load_factor(std::min(1.0, double(n) / ramp));
        m.step();
      }
  }

  // Area of the regular n-gon inscribed in the circle of radius r (the
  // straight-chord cross-section of the mesh).
  double polygon_area(unsigned int n, double r)
  {
    return 0.5 * n * r * r * std::sin(2 * M_PI / n);
  }

} // namespace

TEST_CASE(
    "3D section: the continuum mesh surrounds the section with the tunnel through it",
    "[coupling][section3d][mesh]")
{
  fem::SectionMeshSettings s;
  s.tunnel_radius  = 0.3;
  s.hole_radius    = 0.8;
  s.section_length = 0.9;
  s.end_overlap    = 0.2;
  s.extension      = 2.5;
  s.outer_radius   = 6;
  s.cells_around   = 24;
  s.element_size   = 0.2;
  dealii::Triangulation<3> tria;
  fem::generate_section_mesh(tria, s);

  // Volume (Q1 cells: straight chords, so the n-gon areas are exact):
  // the cylinder minus the tunnel over the whole length minus the hole.
  const unsigned int n      = s.cells_around;
  const double       length = s.section_length + 2 * s.extension;
  const double       exact =
      (polygon_area(n, s.outer_radius) - polygon_area(n, s.tunnel_radius)) * length -
      (polygon_area(n, s.hole_radius) - polygon_area(n, s.tunnel_radius)) *
          (s.section_length - 2 * s.end_overlap);
  const double volume = dealii::GridTools::volume(tria);
  INFO("volume " << volume << " vs " << exact);
  CHECK(std::abs(volume - exact) < 1e-10 * exact);

  // Boundary ids and their extents; areas of the end planes and the
  // tunnel wall; every face bounding the section has id 2.
  std::set<dealii::types::boundary_id> ids;
  double zmin = 1e9, zmax = -1e9, roller_area = 0, wall_area = 0, iface_area = 0;
  for (const auto &cell : tria.active_cell_iterators())
    for (const auto &face : cell->face_iterators())
      if (face->at_boundary())
        {
          const auto   c = face->center();
          const double r = std::hypot(c[0], c[1]);
          ids.insert(face->boundary_id());
          zmin = std::min(zmin, c[2]);
          zmax = std::max(zmax, c[2]);
          switch (face->boundary_id())
            {
            case fem::boundary_id::roller_z:
              roller_area += face->measure();
              break;
            case fem::boundary_id::tunnel_wall:
              wall_area += face->measure();
              CHECK((c[2] < 0 || c[2] > s.section_length));
              CHECK(r < s.tunnel_radius + 1e-9);
              break;
            case fem::boundary_id::interface:
              iface_area += face->measure();
              CHECK(c[2] > -1e-12);
              CHECK(c[2] < s.section_length + 1e-12);
              break;
            case fem::boundary_id::far_field:
              CHECK(r > 0.99 * s.outer_radius);
              break;
            default:
              FAIL("unexpected boundary id " << int(face->boundary_id()));
            }
        }
  CHECK(ids.size() == 4);
  const double ring = polygon_area(n, s.outer_radius) - polygon_area(n, s.tunnel_radius);
  CHECK(std::abs(roller_area - 2 * ring) < 1e-10 * ring);
  const double chord = 2 * std::sin(M_PI / n);
  CHECK(std::abs(wall_area - n * chord * s.tunnel_radius * 2 * s.extension) <
        1e-10 * wall_area);
  // Section faces: the hole's lateral surface, its two annular end caps and
  // the tunnel wall through the two end layers.
  const double hole =
      n * chord * s.hole_radius * (s.section_length - 2 * s.end_overlap) +
      2 * (polygon_area(n, s.hole_radius) - polygon_area(n, s.tunnel_radius)) +
      n * chord * s.tunnel_radius * 2 * s.end_overlap;
  CHECK(std::abs(iface_area - hole) < 1e-10 * hole);
}

TEST_CASE("3D section: DEM force sum on the interface (rim and ends) equals the "
          "continuum's nodal force sum every step",
          "[coupling][section3d]")
{
  test::ensure_mpi_coupling();
  CouplingParams cp;
  cp.subcycles = 2;
  // Section b = 0.6 m, t = 0.6 m, overlap h = 0.2 m; tunnel a = 0.15 m
  // (only its continuum part matters here: no excavation).
  auto  mp = make_coupled_model<3>(section_region(0.6, 0.08, 0.12, 0.6),
                                  section_continuum(20e9, 0.25, 6, 1.5, 0.15), cp,
                                  MPI_COMM_WORLD);
  auto &m  = *mp;
  m.build();
  REQUIRE(m.section());
  // Slaved grains in the end layers inside the rim (r < b - h).
  const auto  &P          = m.dem.particles;
  int          end_slaved = 0;
  int          core_free  = 0;
  const double h          = m.end_overlap();
  for (std::size_t i = 0; i < P.size(); ++i)
    {
      const double r = P.x[i].head<2>().norm();
      if (P.group[i] == SlavedLayerModel<3>::slaved_tag && r < 0.6 - h)
        {
          ++end_slaved;
          CHECK((P.x[i][2] < h || P.x[i][2] > 0.6 - h));
          CHECK(r > 0.15);
        }
      if (P.group[i] != SlavedLayerModel<3>::slaved_tag && r < 0.6 - h && P.x[i][2] > h &&
          P.x[i][2] < 0.6 - h)
        ++core_free;
    }
  INFO(P.size() << " grains, " << end_slaved << " slaved in the end layers, " << core_free
                << " free in the core");
  CHECK(end_slaved > 20);
  CHECK(core_free > 20);

  Eigen::Matrix2d s0;
  s0 << -10e6, 2e6, 2e6, -5e6;
  m.set_insitu(s0);
  double worst = 0, loaded_z = 0;
  for (int n = 0; n < 800; ++n)
    {
      m.set_load_factor(std::min(1.0, n / 500.0));
      m.step();
      worst    = std::max(worst, m.imbalance_last());
      loaded_z = std::max(loaded_z, std::abs(m.interface_force()[2]));
    }
  INFO("max relative imbalance " << worst << ", largest |interface force z| " << loaded_z
                                 << " N");
  // The nodal forces are the DEM forces redistributed by shape functions
  // (partition of unity): equal up to round-off.
  CHECK(worst < 1e-10);
  CHECK(worst == m.imbalance_max());
  // The tunnel-wall traction outside the section: a closed ring of faces
  // under a uniform stress has zero resultant (round-off of the face sums).
  const auto fb = m.continuum().boundary_load_sum();
  CHECK(fb.norm() < 1e-9 * 10e6 * 0.15 * 2 * 1.5);
}

TEST_CASE("3D section: patch test through the ends and excavation convergence vs "
          "plane-strain Kirsch",
          "[coupling][section3d][kirsch]")
{
  // Region b = 1 m, grains 7-10 cm, section 6 mean diameters long with
  // end overlaps of 2 (about 2900 spheres); tunnel a = 0.4 m (a / d = 4.7);
  // far field R = 10 b, continuum 2 m beyond each end.
  test::ensure_mpi_coupling();
  const RegionParams rp = section_region(1.0, 0.07, 0.10, 0.51);
  const double       p = 10e6, q = 3e6, R = 10, L = 2, a = 0.4;
  const double       h = 2 * rp.mean_diameter();
  // Probe (as the slab test): the region's plane-strain constants from its
  // core stress and the coupling nodes' strain under an anisotropic far
  // field: lambda + G = s_m / (2 e_m), G = s_d / (2 e_d).
  double lg = 0, G = 0;
  {
    auto  mp = make_coupled_model<3>(rp, section_continuum(12e9, 0.25, R, L, a),
                                    CouplingParams{}, MPI_COMM_WORLD);
    auto &m  = *mp;
    m.build();
    Eigen::Matrix2d s0;
    s0 << -p - q, 0, 0, -p + q;
    m.set_insitu(s0);
    cycle(m, 2000, 6000);
    const Eigen::Matrix3d s =
        region_stress(m.dem, dem::Vec<3>::Zero(), 0.6, h, rp.slab_thickness - h);
    const auto  u   = m.coupling_displacements();
    const auto &pts = m.coupling_points();
    double      em = 0, ed = 0;
    for (std::size_t k = 0; k < u.size(); ++k)
      {
        const double r2 = pts[k][0] * pts[k][0] + pts[k][1] * pts[k][1];
        em += (u[k][0] * pts[k][0] + u[k][1] * pts[k][1]) / r2;
        ed += (u[k][0] * pts[k][0] - u[k][1] * pts[k][1]) / r2;
      }
    em /= u.size();
    ed /= u.size();
    lg = 0.25 * (s(0, 0) + s(1, 1)) / em;
    G  = 0.25 * (s(0, 0) - s(1, 1)) / ed;
  }
  const double lambda = lg - G;
  const double nu     = lambda / (2 * (lambda + G));
  const double E      = 2 * G * (1 + nu);
  INFO("section constants: lambda+G " << lg << ", G " << G << " -> E " << E << ", nu "
                                      << nu);
  REQUIRE(G > 0);
  REQUIRE(nu > -1);
  REQUIRE(nu < 0.5);

  auto mp = make_coupled_model<3>(rp, section_continuum(E, nu, R, L, a), CouplingParams{},
                                  MPI_COMM_WORLD);
  auto &m = *mp;
  m.build();
  auto                    &P = m.dem.particles;
  std::vector<dem::Vec<3>> start(*std::max_element(P.id.begin(), P.id.end()) + 1);
  for (std::size_t i = 0; i < P.size(); ++i)
    start[P.id[i]] = P.x[i];
  m.set_insitu(-p * Eigen::Matrix2d::Identity());
  cycle(m, 2000, 6000);

  // Patch test: the free core carries the applied in-plane stress.
  const Eigen::Matrix3d s =
      region_stress(m.dem, dem::Vec<3>::Zero(), 0.6, h, rp.slab_thickness - h);
  const double sm  = 0.5 * (s(0, 0) + s(1, 1));
  const double dev = std::hypot(0.5 * (s(0, 0) - s(1, 1)), s(0, 1));
  // The ends: the continuum beyond them is in plane strain, and the end
  // layers slaved to it hold the free core's length: the core's axial
  // strain e_zz (least squares u_z = e_zz (z - t/2) over its free grains)
  // is small against its in-plane strain e_m (u_r = e_m r). szz is the
  // grains' own response to that (the packing between walls is not
  // isotropic: the slab test measured -1.31 MPa where nu (sxx + syy) gives
  // -2.0), so only its sign is a check.
  const double zc = 0.5 * rp.slab_thickness, r_core = m.continuum_inner_radius();
  double       zz = 0, z2 = 0, rr = 0, r2 = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    {
      const dem::Vec<3> X = start[P.id[i]], u = P.x[i] - X;
      const double      r = X.head<2>().norm();
      if (P.group[i] == SlavedLayerModel<3>::slaved_tag || r > r_core - rp.d_hi)
        continue;
      zz += u[2] * (X[2] - zc);
      z2 += (X[2] - zc) * (X[2] - zc);
      rr += u.head<2>().dot(X.head<2>());
      r2 += r * r;
    }
  const double ezz = zz / z2, em = rr / r2;
  INFO("core stress (Pa)\n"
       << s << "\nin-plane mean " << sm << " vs " << -p << ", deviator " << dev
       << "; core strain e_m " << em << ", e_zz " << ezz);
  CHECK(m.dem.unbalanced_ratio() < 1e-3);
  CHECK(std::abs(sm + p) < 0.03 * p); // as the slab (2 % in 2D)
  CHECK(dev < 0.03 * p);
  CHECK(em < 0);
  CHECK(std::abs(ezz) < 0.05 * std::abs(em));
  CHECK(s(2, 2) < 0);
  CHECK(std::abs(s(0, 2)) < 0.03 * p);
  CHECK(std::abs(s(1, 2)) < 0.03 * p);
  const auto field0 = m.displacement_field(); // in-situ state of the continuum

  // Excavation along the whole length: the section's grains inside the
  // tunnel are removed and the continuum's tunnel wall released.
  std::vector<dem::Vec<3>> ref(start.size());
  for (std::size_t i = 0; i < P.size(); ++i)
    ref[P.id[i]] = P.x[i];
  std::vector<char> rm(P.size());
  for (std::size_t i = 0; i < P.size(); ++i) // slaved grains stay (demfem tunnel's rule)
    rm[i] = P.x[i].head<2>().norm() < a && P.group[i] != SlavedLayerModel<3>::slaved_tag;
  m.dem.remove_particles(rm);
  m.set_excavation_release(0);
  m.dem.reset_energy_baseline();
  cycle(m, 1, 10000);

  // Kirsch (hydrostatic): u_r = -p a^2 / (2 G r). Fit C over the free core
  // grains (h < z < t - h) between two diameters from the wall and two from
  // the rim, and the wall grains' u_r r / a over the whole section (end
  // layers too).
  const auto   fit = test::kirsch_fit(P, ref, a, rp.mean_diameter(),
                                      m.continuum_inner_radius(), h, rp.slab_thickness - h);
  const double uw  = fit.wall;
  const int    n   = fit.n_wall;
  const double C = fit.C, C_kirsch = -p * a * a / (2 * G);
  const double uw_kirsch = -p * a / (2 * G);

  // The continuum's own tunnel wall far from the section (|z - t/2| > t/2 +
  // L/2): its traction released, it converges as Kirsch too (the
  // excavation-induced part: minus the in-situ state).
  auto field = m.displacement_field();
  field -= field0;
  double uc = 0;
  int    nc = 0;
  for (const auto &cell : m.dof_handler().active_cell_iterators())
    for (const unsigned int v : cell->vertex_indices())
      {
        const auto   x = cell->vertex(v);
        const double r = std::hypot(x[0], x[1]);
        if (std::abs(r - a) < 1e-9 &&
            (x[2] < -0.5 * L || x[2] > rp.slab_thickness + 0.5 * L))
          {
            uc += (field(cell->vertex_dof_index(v, 0)) * x[0] +
                   field(cell->vertex_dof_index(v, 1)) * x[1]) /
                  r;
            ++nc;
          }
      }
  uc /= nc;
  INFO("fit C " << C << " vs Kirsch " << C_kirsch << " (" << C / C_kirsch - 1
                << "); wall grains (" << n << ") u_r r / a " << uw << " vs Kirsch "
                << uw_kirsch << " (" << uw / uw_kirsch - 1 << "); continuum wall (" << nc
                << " vertex visits) u_r " << uc << " (" << uc / uw_kirsch - 1
                << "); imbalance max " << m.imbalance_max() << "; unbalanced ratio "
                << m.dem.unbalanced_ratio());
  CHECK(m.dem.unbalanced_ratio() < 1e-3);
  CHECK(std::abs(C / C_kirsch - 1) < 0.15); // 3D within 15 %
  CHECK(std::abs(uw / uw_kirsch - 1) < 0.15);
  // Q1 continuum, fixed far field at R = 10 b: a few per cent.
  CHECK(std::abs(uc / uw_kirsch - 1) < 0.05);
  CHECK(m.imbalance_max() < 1e-10);
}

TEST_CASE("3D section: demfem tunnel runs a tunnel section in a 3D continuum",
          "[coupling][section3d][app]")
{
  // apps/examples/tunnel_3d_section.prm, small: region 0.9 m, tunnel 0.3 m,
  // unbreakable, short phases: the in-situ state is reached, the phases end
  // at their step limit (not_equilibrated, accepted). The in-situ stress is
  // installed kinematically with the continuum's constants, so they must be
  // this section's: it (about 1 500 spheres, 6 grains thick) is stiffer
  // than the example's larger section. With the example's 13.8 GPa / 0.11
  // its stress missed sigma0 by 11.0 % (yy -22.2 MPa for -20; tolerance
  // 10 %), independent of the ramp (500 or 1000 steps); E 15.1 GPa, nu
  // 0.12 matches its mean in-plane stress (-15.03 MPa for -15), leaving
  // its fabric's anisotropy (xx -5.7 %, yy +3.2 %): 3.9 %. With the in-situ
  // servo (docs/tunnel.md, "In-situ stress servo") 0.4 % at its last
  // measurement, but the release and the in-situ cracking are cut by the
  // step limit here, mid-relaxation: 2.9 % measured, so the tolerance is
  // 5 % (the default 2 % is for equilibrated phases).
  const std::string dir    = std::filesystem::temp_directory_path() / "demfem_section_3d";
  const int         status = test::run_tunnel_example(
              "tunnel_3d_section.prm", dir,
              "--set \"DEM region/radius=0.9\" --set \"Tunnel/radius=0.3\" "
                      "--set \"DEM region/breakable=false\" --set \"Continuum/outer radius=8\" "
                      "--set \"Continuum/young modulus=15.1e9\" --set \"Continuum/poisson ratio=0.12\" "
                      "--set \"Continuum/axial extension=1.2\" --set \"DEM region/slab thickness=6\" "
                      "--set \"Coupling/ramp crossing times=3.5\" --set \"Coupling/step limit=1000\" "
                      "--set \"Output/interval=500\" --set \"Tunnel/in situ tolerance=0.05\" "
                      "--accept not_equilibrated");
  INFO(read_file(dir + ".log"));
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  // unbreakable: no damage, so no warning about the free core's length
  CHECK(read_file(dir + ".log").find("free core") == std::string::npos);
  const std::string summary = read_file(dir + "/summary.json");
  CHECK(summary.find("\"embedding\": \"section\"") != std::string::npos);
  CHECK(summary.find("\"axial_extension\": 1.2") != std::string::npos);
  CHECK(summary.find("\"status\": \"not_equilibrated\"") != std::string::npos);
  CHECK(summary.find("in_situ_not_reached") == std::string::npos);
  // VTK read back by VTK's own readers: grains in 0 .. t = 6 x 0.1 m, the
  // continuum over -L .. t + L.
  const int vs = test::check_vtk_3d(dir, "0.6", "1.2");
  INFO(read_file(dir + ".log.vtk"));
  CHECK(WIFEXITED(vs));
  CHECK(WEXITSTATUS(vs) == 0);
}

TEST_CASE("3D section: a stopped and restarted run equals the uninterrupted one",
          "[coupling][section3d][restart]")
{
  // The section's own state (the release of the continuum's tunnel wall)
  // is in the checkpoint: stopped inside the first of two excavation stages
  // and continued, the run ends bit for bit as the uninterrupted one. Small
  // breakable section (the app test's: b 0.9 m, t 0.6 m, L 1.2 m).
  test::ensure_mpi_coupling();
  auto small = [](const std::string &dir) {
    coupling::TunnelParams p;
    p.output_directory = dir;
    p.dimension        = 3;
    p.tunnel_radius    = 0.3;
    p.sigma0 << -10e6, 0, 0, -20e6;
    p.region                    = section_region(0.9, 0.08, 0.12, 0.6);
    p.region.breakable          = true;
    p.region.fj_ten             = 4e6;
    p.region.fj_coh             = 20e6;
    p.continuum.young_modulus   = 14.2e9;
    p.continuum.poisson_ratio   = 0.12;
    p.continuum.outer_radius    = 8;
    p.continuum.axial_extension = 1.2;
    p.stages                    = 2;
    p.ramp_crossing_times       = 3.5; // about 500 steps
    p.phase_step_limit          = 600;
    p.write_vtk                 = false;
    p.vtk_interval              = 0;
    p.history_interval          = 50;
    p.checkpoint_interval       = 250;
    p.prm_text = "set axial extension = 1.2\nset output directory = " + dir + "\n";
    return p;
  };
  const auto        tmp = std::filesystem::temp_directory_path();
  const std::string da  = tmp / "demfem_section_restart_a",
                    db  = tmp / "demfem_section_restart_b";
  std::filesystem::remove_all(da);
  std::filesystem::remove_all(db);
  std::ostringstream log;
  const auto         ra = coupling::run_tunnel(small(da), log);
  INFO(ra.diagnosis);
  REQUIRE_FALSE(ra.diverged);
  // Breakable, 0.6 m long with two free diameters between its end layers:
  // warned that it is no plane-strain damage model.
  CHECK_THAT(log.str(), Catch::Contains("warning: the section's free core"));
  auto pb         = small(db);
  pb.stop_at_step = 1300; // ramp 500 + in-situ equilibrium <= 600: in stage 1
  const auto rb   = coupling::run_tunnel(pb, log);
  REQUIRE(rb.interrupted);
  auto pc         = small(db);
  pc.restart_file = db + "/checkpoint.h5";
  const auto rc   = coupling::run_tunnel(pc, log);
  REQUIRE_FALSE(rc.interrupted);
  REQUIRE_FALSE(rc.diverged);
  INFO("cracks " << ra.cracks_total << ", convergence " << ra.wall_convergence_mean);
  CHECK(rc.steps == ra.steps);
  CHECK(rc.cracks_total == ra.cracks_total);
  CHECK(rc.wall_convergence_mean == ra.wall_convergence_mean);
  CHECK(rc.interface_force_imbalance_max == ra.interface_force_imbalance_max);
  REQUIRE(rc.positions_3d.size() == ra.positions_3d.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < ra.positions_3d.size(); ++i)
    differ += !(rc.positions_3d[i] == ra.positions_3d[i]);
  CHECK(differ == 0);
  CHECK(read_file(db + "/history.csv") == read_file(da + "/history.csv"));
}

TEST_CASE("3D section: bad input names the key", "[coupling][section3d][input]")
{
  test::ensure_mpi_coupling();
  const RegionParams rp      = section_region(0.6, 0.08, 0.12, 0.6);
  auto               message = [&](CouplingParams cp, ContinuumParams cc) -> std::string {
    try
      {
        auto mp = make_coupled_model<3>(rp, cc, cp, MPI_COMM_WORLD);
        mp->build();
      }
    catch (const dem::InputError &e)
      {
        return e.what();
      }
    return "";
  };
  CouplingParams facets;
  facets.variant = "wall-facets";
  CHECK_THAT(message(facets, section_continuum(20e9, 0.25, 6, 1.5, 0.15)),
             Catch::Contains("Continuum/axial extension") &&
                 Catch::Contains("slaved-layer"));
  CouplingParams qs;
  qs.scheme = "quasi-static";
  CHECK_THAT(message(qs, section_continuum(20e9, 0.25, 6, 1.5, 0.15)),
             Catch::Contains("Continuum/axial extension") && Catch::Contains("explicit"));
  CHECK_THAT(message(CouplingParams{}, section_continuum(20e9, 0.25, 6, -1, 0.15)),
             Catch::Contains("axial extension"));
  // Both end overlaps (2 x 0.2 m) and a grain do not fit in 0.45 m.
  RegionParams thin   = rp;
  thin.slab_thickness = 0.45;
  try
    {
      auto mp = make_coupled_model<3>(thin, section_continuum(20e9, 0.25, 6, 1.5, 0.15),
                                      CouplingParams{}, MPI_COMM_WORLD);
      mp->build();
      FAIL("a section thinner than its two end overlaps was accepted");
    }
  catch (const dem::InputError &e)
    {
      CHECK_THAT(std::string(e.what()), Catch::Contains("DEM region/slab thickness"));
    }
  // 2D with an axial extension: refused by the model.
  try
    {
      RegionParams r2   = rp;
      r2.slab_thickness = 0;
      auto mp = make_coupled_model<2>(r2, section_continuum(20e9, 0.25, 6, 1.5, 0.15),
                                      CouplingParams{}, MPI_COMM_WORLD);
      FAIL("an axial extension was accepted in 2D");
    }
  catch (const dem::InputError &e)
    {
      CHECK_THAT(std::string(e.what()), Catch::Contains("Continuum/axial extension") &&
                                            Catch::Contains("dimension = 3"));
    }
}
