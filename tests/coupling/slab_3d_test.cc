// The 3D coupled slab (a slab of the 2D problem, plane strain through
// walls): DEM spheres in 0 < z < t between fixed frictionless walls,
// embedded in the annulus extruded over the same thickness with rollers on
// its z faces (coupled_model.h). Force balance across the interface, the
// embedded patch test and the excavation convergence vs plane-strain Kirsch.
#include <catch2/catch.hpp>

#include "coupling/coupled_model.h"
#include "coupling/slaved_layer_model.h"
#include "coupling/wall_facet_model.h"
#include "helpers.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using namespace demfem;
using namespace demfem::coupling;

namespace
{
  RegionParams slab(double b, double d_lo, double d_hi, double t)
  {
    return test::slab_region(b, d_lo, d_hi, t);
  }

  ContinuumParams continuum(double E, double nu, double R)
  {
    ContinuumParams c;
    c.young_modulus = E;
    c.poisson_ratio = nu;
    c.outer_radius  = R;
    return c;
  }

  void load(CoupledModel<3> &m, int ramp, int total)
  {
    for (int n = 0; n < total; ++n)
      {
        m.set_load_factor(std::min(1.0, double(n) / ramp));
        m.step();
      }
  }

  // Mean radial and deviatoric in-plane strain of the coupling nodes (the
  // nodes of the slaved layer's cells, rings symmetric about x and y).
  std::pair<double, double> ring_strain(const CoupledModel<3> &m)
  {
    const auto  u   = m.coupling_displacements();
    const auto &pts = m.coupling_points();
    double      em = 0, ed = 0;
    for (std::size_t k = 0; k < u.size(); ++k)
      {
        const double r2 = pts[k][0] * pts[k][0] + pts[k][1] * pts[k][1];
        em += (u[k][0] * pts[k][0] + u[k][1] * pts[k][1]) / r2;
        ed += (u[k][0] * pts[k][0] - u[k][1] * pts[k][1]) / r2;
      }
    return {em / u.size(), ed / u.size()};
  }
} // namespace

TEST_CASE("3D slab: DEM force sum on the interface equals the continuum's nodal force "
          "sum every step",
          "[coupling][slab3d]")
{
  test::ensure_mpi_coupling();
  const std::string variant = GENERATE(as<std::string>{}, "slaved-layer", "wall-facets");
  INFO("Coupling/variant = " << variant);
  CouplingParams cp;
  cp.variant   = variant;
  cp.subcycles = 2;
  // Wall facets in 3D: the coupled explicit step is unstable at safety 0.8
  // (detected: kinetic-energy growth, InstabilityError), stable at 0.4
  // (measured; docs/tunnel.md).
  if (variant == "wall-facets")
    cp.safety = 0.4;
  auto  mp = make_coupled_model<3>(slab(0.6, 0.08, 0.12, 0.4), continuum(20e9, 0.25, 6),
                                  cp, MPI_COMM_WORLD);
  auto &m  = *mp;
  m.build();
  Eigen::Matrix2d s0;
  s0 << -10e6, 2e6, 2e6, -5e6;
  m.set_insitu(s0);
  double worst = 0, loaded = 0;
  for (int n = 0; n < 800; ++n)
    {
      m.set_load_factor(std::min(1.0, n / 500.0));
      m.step();
      worst  = std::max(worst, m.imbalance_last());
      loaded = std::max(loaded, m.interface_force().norm());
    }
  INFO(m.dem.particles.size() << " grains, " << m.coupling_points().size()
                              << " coupling nodes; max relative imbalance " << worst
                              << ", largest interface force " << loaded << " N");
  CHECK(loaded > 0);
  CHECK(worst == m.imbalance_max());
  // The nodal forces are the DEM forces redistributed by weights summing
  // to 1 (barycentric weights, shape functions): equal up to round-off.
  CHECK(worst < 1e-10);
}

TEST_CASE("3D slab: patch test and excavation convergence vs plane-strain Kirsch",
          "[coupling][slab3d][kirsch]")
{
  // Region b = 1 m, grains 7-10 cm, slab three mean diameters thick (about
  // 1500 spheres); tunnel a = 0.4 m (a / d = 4.7); far field R = 10 b.
  test::ensure_mpi_coupling();
  const RegionParams rp = slab(1.0, 0.07, 0.10, 0.255);
  const double       p = 10e6, q = 3e6, R = 10;
  // Probe: anisotropic in-plane far field; the region's plane-strain
  // constants from its centre stress and the coupling nodes' strain
  // (uniform strain inside a circular inclusion whatever the matrix,
  // Eshelby): lambda + G = s_m / (2 e_m), G = s_d / (2 e_d).
  double lg = 0, G = 0;
  {
    auto  mp = make_coupled_model<3>(rp, continuum(12e9, 0.25, R), CouplingParams{},
                                    MPI_COMM_WORLD);
    auto &m  = *mp;
    m.build();
    Eigen::Matrix2d s0;
    s0 << -p - q, 0, 0, -p + q;
    m.set_insitu(s0);
    load(m, 2000, 6000);
    const Eigen::Matrix3d s =
        region_stress(m.dem, dem::Vec<3>::Zero(), 0.6, rp.slab_thickness);
    const auto [em, ed] = ring_strain(m);
    lg                  = 0.25 * (s(0, 0) + s(1, 1)) / em;
    G                   = 0.25 * (s(0, 0) - s(1, 1)) / ed;
  }
  const double lambda = lg - G;
  const double nu     = lambda / (2 * (lambda + G));
  const double E      = 2 * G * (1 + nu);
  INFO("slab constants: lambda+G " << lg << ", G " << G << " -> E " << E << ", nu "
                                   << nu);
  REQUIRE(G > 0);
  REQUIRE(nu > -1);
  REQUIRE(nu < 0.5);

  auto mp =
      make_coupled_model<3>(rp, continuum(E, nu, R), CouplingParams{}, MPI_COMM_WORLD);
  auto &m = *mp;
  m.build();
  m.set_insitu(-p * Eigen::Matrix2d::Identity());
  load(m, 2000, 6000);

  // Patch test: the centre of the slab carries the applied in-plane stress.
  const Eigen::Matrix3d s =
      region_stress(m.dem, dem::Vec<3>::Zero(), 0.6, rp.slab_thickness);
  const double sm  = 0.5 * (s(0, 0) + s(1, 1));
  const double dev = std::hypot(0.5 * (s(0, 0) - s(1, 1)), s(0, 1));
  INFO("centre stress (Pa)\n"
       << s << "\nin-plane mean " << sm << " vs " << -p << ", deviator " << dev);
  CHECK(m.dem.unbalanced_ratio() < 1e-3);
  CHECK(std::abs(sm + p) < 0.03 * p); // 2 % in 2D; 3 % for the slab
  CHECK(dev < 0.03 * p);
  CHECK(s(2, 2) < 0); // plane strain: the slab walls push back (szz = nu' (sxx + syy))

  // Excavation.
  const double             a = 0.4;
  auto                    &P = m.dem.particles;
  std::vector<dem::Vec<3>> ref(*std::max_element(P.id.begin(), P.id.end()) + 1);
  for (std::size_t i = 0; i < P.size(); ++i)
    ref[P.id[i]] = P.x[i];
  std::vector<char> rm(P.size());
  for (std::size_t i = 0; i < P.size(); ++i)
    rm[i] = P.x[i].head<2>().norm() < a;
  m.dem.remove_particles(rm);
  m.dem.reset_energy_baseline();
  load(m, 1, 10000);

  const auto fit =
      test::kirsch_fit(P, ref, a, rp.mean_diameter(), m.continuum_inner_radius());
  const double uw = fit.wall;
  const int    n  = fit.n_wall;
  const double C = fit.C, C_kirsch = -p * a * a / (2 * G);
  const double uw_kirsch = -p * a / (2 * G);
  INFO("fit C " << C << " vs Kirsch " << C_kirsch << " (" << C / C_kirsch - 1
                << "); wall grains (" << n << ") u_r r / a " << uw << " vs Kirsch "
                << uw_kirsch << " (" << uw / uw_kirsch - 1 << "); imbalance max "
                << m.imbalance_max() << "; unbalanced ratio "
                << m.dem.unbalanced_ratio());
  CHECK(m.dem.unbalanced_ratio() < 1e-3);
  CHECK(std::abs(C / C_kirsch - 1) < 0.15); // 3D slab within 15 %
  CHECK(std::abs(uw / uw_kirsch - 1) < 0.15);
  CHECK(m.imbalance_max() < 1e-10);
}

TEST_CASE("3D slab: demfem tunnel runs the slab and writes readable 3D output",
          "[coupling][slab3d][app]")
{
  // A small version of apps/examples/tunnel_3d.prm: region 0.9 m, tunnel
  // 0.3 m, unbreakable, short phases: long enough for the in-situ state
  // (measured 4 % off sigma0 before the in-situ servo; with 500 ramp + 1000
  // steps it was 32 % off and the run said in_situ_not_reached), too short
  // for the continuum's kinetic energy to decay to 1e-4 of its peak:
  // not_equilibrated, accepted. With the servo: 8.9 % held, 0.48 % after
  // two corrections, 1.8 % after the release and the in-situ cracking cut
  // mid-relaxation by the step limit; the tolerance is 5 % (the default 2 %
  // is for equilibrated phases; docs/tunnel.md, "In-situ stress servo").
  const std::string dir    = std::filesystem::temp_directory_path() / "demfem_tunnel_3d";
  const int         status = test::run_tunnel_example(
              "tunnel_3d.prm", dir,
              "--set \"DEM region/radius=0.9\" --set \"Tunnel/radius=0.3\" "
                      "--set \"DEM region/breakable=false\" --set \"Continuum/outer "
                      "radius=8\" --set \"Coupling/ramp crossing times=7\" --set "
                      "\"Coupling/step limit=2000\" --set \"Output/interval=500\" "
                      "--set \"Tunnel/in situ tolerance=0.05\" --accept not_equilibrated");
  const auto read = test::read_file;
  INFO(read(dir + ".log"));
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  const std::string summary = read(dir + "/summary.json");
  CHECK(summary.find("\"dimension\": 3") != std::string::npos);
  CHECK(summary.find("\"status\": \"not_equilibrated\"") != std::string::npos);
  CHECK(summary.find("in_situ_not_reached") == std::string::npos);
  CHECK(summary.find("region_stress_zz_before_excavation") != std::string::npos);
  const std::string history = read(dir + "/history.csv");
  CHECK(history.find("ring_force_z") != std::string::npos);
  // wall_displacement.csv: x,y,z,ux,uy,uz with z inside the slab (3 mean
  // diameters = 0.3 m) for every wall grain.
  std::ifstream wd(dir + "/wall_displacement.csv");
  std::string   line;
  std::getline(wd, line);
  CHECK(line == "x,y,z,ux,uy,uz");
  int    rows = 0;
  double zmax = 0;
  while (std::getline(wd, line))
    {
      std::stringstream ls(line);
      std::string       cell;
      double            v[6];
      for (int c = 0; c < 6; ++c)
        {
          std::getline(ls, cell, ',');
          v[c] = std::stod(cell);
        }
      CHECK(v[2] > 0);
      CHECK(v[2] < 0.3);
      zmax = std::max(zmax, v[2]);
      ++rows;
    }
  CHECK(rows > 20);
  CHECK(zmax > 0.15);
  // VTK read back by VTK's own readers (python3-vtk9).
  const int vs = test::check_vtk_3d(dir, "0.3");
  INFO(read(dir + ".log.vtk"));
  CHECK(WIFEXITED(vs));
  CHECK(WEXITSTATUS(vs) == 0);
}

TEST_CASE("3D slab: the quasi-static and condensed schemes reach the explicit scheme's "
          "in-situ state",
          "[coupling][slab3d][quasistatic]")
{
  // Same packing, same far field: the in-situ equilibrium does not depend on
  // the time scheme. Compared: the coupling nodes' displacements (the
  // interface state both schemes converge to) and the free grains'
  // Love-Weber stress. Both runs end at unbalanced ratios below 1e-6, and
  // what differs is the load path: the frictional contacts of the carved
  // region slip a little differently while the explicit continuum
  // oscillates. Measured differences 3.2e-4 / 1.3e-4 (displacements,
  // quasi-static / condensed) and 1.6e-4 / 6.6e-5 (stress); a scheme that
  // solved another static problem differs by percents: limits 1e-3, as in
  // 2D (quasi_static_test.cc).
  test::ensure_mpi_coupling();
  auto run = [](const std::string &scheme) {
    CouplingParams cp;
    cp.scheme = scheme;
    if (scheme == "quasi-static")
      cp.subcycles = 200, cp.relaxation = 0.3;
    auto  mp = make_coupled_model<3>(slab(0.6, 0.08, 0.12, 0.4), continuum(20e9, 0.25, 6),
                                    cp, MPI_COMM_WORLD);
    auto &m  = *mp;
    m.build();
    Eigen::Matrix2d s0;
    s0 << -10e6, 0, 0, -5e6;
    m.set_insitu(s0);
    // Installed over 2 ms, then relaxed to ratios of 1e-6 (both schemes
    // settle within 0.035 s).
    const bool settled = test::install_insitu(m, 2e-3, 0.1, 1e-6);
    INFO(scheme << ": unbalanced ratio " << m.dem.unbalanced_ratio());
    CHECK(settled);
    return std::make_pair(m.coupling_displacements(),
                          region_stress(m.dem, dem::Vec<3>::Zero(), 0.3, 0.4));
  };
  const auto [ue, se] = run("explicit");
  // The condensed scheme as well (its interface stiffness has the roller's
  // constrained z components removed, coupling_scheme.cc).
  const std::string scheme = GENERATE(as<std::string>{}, "quasi-static", "condensed");
  INFO("Coupling/scheme = " << scheme);
  const auto [uq, sq] = run(scheme);
  REQUIRE(ue.size() == uq.size());
  double diff = 0, norm = 0;
  for (std::size_t k = 0; k < ue.size(); ++k)
    diff += (ue[k] - uq[k]).squaredNorm(), norm += ue[k].squaredNorm();
  INFO("relative difference of the coupling displacements "
       << std::sqrt(diff / norm) << "; centre stress xx " << se(0, 0) << " vs "
       << sq(0, 0));
  CHECK(std::sqrt(diff / norm) < 1e-3);
  CHECK(std::abs(sq(0, 0) - se(0, 0)) < 1e-3 * std::abs(se(0, 0)));
  CHECK(std::abs(sq(1, 1) - se(1, 1)) < 1e-3 * std::abs(se(1, 1)));
}
