// Confined and uniaxial-strain compression (fistPkg §5.5, Table 10): the
// servo holds the confining pressure on the lateral walls through the
// loading phase, up to and past the peak; in uniaxial strain (lateral walls
// fixed) the lateral/axial stress-increment ratio is the closed form of the
// specimen's own Poisson ratio; the confined modulus equals the unconfined
// one in the elastic range. Flexible lateral walls (2D; dem/specimen/
// vessel.h, servo.h; docs/calibrate.md, "Confining servo"): the tributary
// areas of the wall's vertices integrate the platen gap exactly, the
// wall's length is their weighted mean position, each vertex holds Pc on
// its own, the test holds Pc up to the peak; bad segment counts are
// refused naming the key. The pressure boundary (2D; dem/specimen/
// pressure_boundary.h): the unconfined moduli, the regions at -Pc, the
// post-peak end independent of the time step, refused where it does not
// apply.
#include "dem/specimen/genesis.h"
#include "dem/specimen/lab_tests.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <numeric>
#include <string>

using namespace demfem::dem;

namespace
{
  // Flat-jointed material of about 250 grains (as in lab_tests_test.cc);
  // strengths 1e15 Pa: elastic, unless set otherwise.
  MaterialParams material(double ten_mean, double ten_sd, double coh)
  {
    MaterialParams p;
    p.type     = "flatjointed";
    p.sizes    = {SizePiece{false, 1.0e-3, 1.66e-3, 0, 0, 1.0}};
    p.lnm_emod = 4e10;
    p.lnm_krat = 1.5;
    p.emod     = 4e10;
    p.krat     = 2.0;
    p.fric     = 0.4;
    p.fj_B     = 1;
    p.fj_G     = 0;
    p.fj_ten   = {ten_mean, ten_sd};
    p.fj_coh   = {coh, 0};
    p.fj_fa    = 30;
    p.Pm       = 1e5;
    return p;
  }

  MaterialParams elastic() { return material(1e15, 0, 1e15); }

  VesselParams box2d()
  {
    VesselParams v;
    v.W = 0.03, v.H = 0.06;
    return v;
  }

  VesselParams cylinder3d()
  {
    VesselParams v;
    v.shape = "cylinder";
    v.W = 0.02, v.H = 0.04;
    return v;
  }

  // Elastic range: the axial strain stops at 2e-4 (about 4 MPa of deviator
  // on E ~ 20 GPa), and the "peak" is the last row. The servo is
  // proportional (Itasca 2008 §3.10.5): its lag grows with the wall speed it
  // must follow, so the rate is kept low enough for 1 % (measured on this
  // specimen: 0.6 % at 0.3/s, 1.0 % at 0.5/s, 2 % at 1/s).
  LabTestParams elastic_test(CompressionType ctype, double Pc)
  {
    LabTestParams l;
    l.kind             = TestKind::compression;
    l.ctype            = ctype;
    l.Pc               = Pc;
    l.strain_rate      = 0.3;
    l.strain_limit     = 2e-4;
    l.history_interval = 20;
    l.fit_lo = 0.2, l.fit_hi = 0.9;
    return l;
  }

  template <int dim>
  Specimen<dim> make_specimen(const MaterialParams &p0, const VesselParams &v, double n)
  {
    MaterialParams p = p0;
    set_grain_count<dim>(p, v, n);
    return build_specimen<dim>(p, v);
  }

  template <int dim>
  LabTestResult run(const MaterialParams &p0, const VesselParams &v, double n,
                    const LabTestParams &l)
  {
    Specimen<dim> s = make_specimen<dim>(p0, v, n);
    return run_lab_test(s, l);
  }

  // The elastic test confined by flexible walls of n facets.
  LabTestParams flexible_test(double Pc, int n)
  {
    LabTestParams l    = elastic_test(CompressionType::confined, Pc);
    l.lateral_segments = n;
    return l;
  }

  // Least-squares slope of the lateral wall stress against the axial wall
  // stress over the fit window of the loading branch.
  // The flexible walls' breakable test (4 facets) to the post-peak end.
  LabTestParams flexible_breakable_test(double Pc)
  {
    LabTestParams l = flexible_test(Pc, 4);
    l.strain_limit  = 0.02;
    l.strain_rate   = 0.15;
    l.load_fraction = 0.8;
    l.fit_lo = 0.1, l.fit_hi = 0.5;
    return l;
  }

  double lateral_to_axial_ratio(const LabTestResult &r, const LabTestParams &l,
                                bool regions)
  {
    std::vector<double> sa, sl;
    for (std::size_t i = 0; i <= r.peak_row; ++i)
      {
        const auto &h = r.history[i];
        if (h.load >= l.fit_lo * r.peak_load && h.load <= l.fit_hi * r.peak_load)
          {
            if (regions)
              sa.push_back(h.region_axial_stress), sl.push_back(h.region_lateral_stress);
            else
              sa.push_back(h.axial_stress), sl.push_back(h.lateral_wall_stress);
          }
      }
    return ls_slope(sa, sl);
  }
} // namespace

TEST_CASE("confined compression: the servo holds Pc up to and past the peak (2D)",
          "[labtests][confined]")
{
  // Breakable material (tensile strength 20 +- 6 MPa, cohesion 60 MPa),
  // confined at 5 MPa; the test ends on the post-peak rule, so the history
  // covers the peak and the softening branch behind it.
  const double  Pc = 5e6;
  LabTestParams l  = elastic_test(CompressionType::confined, Pc);
  l.strain_limit   = 0.02;
  l.strain_rate    = 0.15;
  l.load_fraction  = 0.8;
  l.fit_lo = 0.1, l.fit_hi = 0.5;
  const LabTestResult r  = run<2>(material(20e6, 6e6, 60e6), box2d(), 250, l);
  const HistoryRow   &pk = r.history[r.peak_row];
  INFO("peak " << r.peak << " Pa at row " << r.peak_row << " of " << r.history.size()
               << ", ended by " << r.ended_by << ", Pc deviation to peak "
               << r.confining_deviation_to_peak << ", overall " << r.confining_deviation
               << ", lateral at peak " << pk.lateral_wall_stress << ", sigma_cd "
               << r.crack_damage << ", sigma_ci " << r.crack_initiation);
  REQUIRE(r.ended_by == "post-peak");
  CHECK(r.lateral_wall_segments == 1); // rigid walls (flexible: below)
  // The peak is a material failure well above the confinement.
  CHECK(r.peak > 3 * Pc);
  // Up to the peak the wall stress, averaged over a wave's crossing time
  // (56 steps here), stays within 1 % of Pc: measured 0.74 % (2.8 % with
  // the proportional servo, sampled at the history rows). Each lateral
  // wall carries about 15 grain contacts, so a crack next to it kicks the
  // instantaneous stress by several % for a few steps (spikes measured up
  // to 9 %). Past the peak the specimen dilates dynamically along its
  // shear band (measured up to 45 %): reported, not held.
  CHECK(r.confining_deviation_to_peak < 0.01);
  CHECK(r.confining_deviation >= r.confining_deviation_to_peak);
  CHECK(r.confining_spike_to_peak >= r.confining_deviation_to_peak);
  // One history row's instantaneous value: a spike may fall on it.
  CHECK(pk.lateral_wall_stress == Approx(-Pc).epsilon(0.04));
  // Cracking starts before the peak; the volumetric strain reverses
  // (dilatancy) between crack initiation and the peak.
  CHECK(r.crack_initiation < r.peak);
  CHECK(r.crack_damage > r.crack_initiation);
  CHECK(r.crack_damage <= r.peak);
}

TEST_CASE("confined compression: the servo holds Pc on the 3D cylinder wall",
          "[labtests][confined]")
{
  // Elastic 3D cylinder of about 400 spheres, confined at 2 MPa by the
  // servo on its cylinder wall while the platens load it.
  const double        Pc = 2e6;
  const LabTestParams l  = elastic_test(CompressionType::confined, Pc);
  const LabTestResult r  = run<3>(elastic(), cylinder3d(), 400, l);
  INFO("Pc deviation " << r.confining_deviation << ", peak deviator " << r.peak_load
                       << ", E " << r.E << ", nu " << r.nu);
  REQUIRE(r.peak_load > Pc);
  CHECK(r.confining_deviation < 0.01);
}

TEST_CASE("confined compression: the servo's integral term removes the lag: the "
          "deviation does not depend on the history interval (2D)",
          "[labtests][confined]")
{
  // Elastic specimen at 1/s: the lateral walls must keep moving outward as
  // the platens close, which a proportional servo follows only with an
  // error e = v / G (measured 1.9 % here, 0.17 % with the integral term,
  // which learns the velocity: dem/specimen/servo.h). The seating runs at
  // most at Pc / (rho c): at Table 10's 10 eps_rate H (0.6 m/s) it failed
  // the energy check.
  const double  Pc       = 2e6;
  LabTestParams l        = elastic_test(CompressionType::confined, Pc);
  l.strain_rate          = 1.0;
  LabTestParams p        = l;
  p.servo.integral_gain  = 0;
  const LabTestResult pr = run<2>(elastic(), box2d(), 250, p);
  const LabTestResult pi = run<2>(elastic(), box2d(), 250, l);
  LabTestParams       h  = l;
  h.history_interval     = 7;
  const LabTestResult ph = run<2>(elastic(), box2d(), 250, h);
  INFO("Pc deviation: proportional " << pr.confining_deviation_to_peak << ", with the "
                                     << "integral term " << pi.confining_deviation_to_peak
                                     << " (spikes " << pi.confining_spike_to_peak
                                     << "), window " << pi.confining_window << " s");
  CHECK(pr.confining_deviation_to_peak > 0.01);
  CHECK(pi.confining_deviation_to_peak < 0.2 * pr.confining_deviation_to_peak);
  CHECK(pi.confining_spike_to_peak >= pi.confining_deviation_to_peak);
  // The window: the crossing time of a wave at sqrt(E*/rho) over W.
  CHECK(pi.confining_window == Approx(0.03 / std::sqrt(4e10 / 2650)).epsilon(0.01));
  // Every step is sampled and the strain limit checked every step: the
  // history rows do not enter.
  CHECK(ph.confining_deviation_to_peak == pi.confining_deviation_to_peak);
  CHECK(ph.peak == pi.peak);
}

TEST_CASE("confined modulus equals the unconfined one in the elastic range (2D)",
          "[labtests][confined]")
{
  // Linear elasticity: sigma_3 held constant, d sigma_1 = E d eps_1 and
  // d eps_3 = -nu d eps_1 whatever the confinement; the bonded contacts are
  // linear and unbreakable, so only the contacts the confinement closes
  // (unbonded, linear group) can stiffen the specimen.
  const LabTestResult u =
      run<2>(elastic(), box2d(), 250, elastic_test(CompressionType::unconfined, 0));
  const LabTestResult c =
      run<2>(elastic(), box2d(), 250, elastic_test(CompressionType::confined, 2e6));
  INFO("unconfined E' " << u.E_ps << " nu' " << u.nu_ps << "; confined E' " << c.E_ps
                        << " nu' " << c.nu_ps << ", Pc deviation "
                        << c.confining_deviation);
  REQUIRE(u.E_ps > 0);
  CHECK(c.E_ps == Approx(u.E_ps).epsilon(0.05));
  CHECK(c.nu_ps == Approx(u.nu_ps).margin(0.025));
  CHECK(c.confining_deviation < 0.01);
}

TEST_CASE("uniaxial strain: lateral/axial stress increments follow the measured nu (2D)",
          "[labtests][confined]")
{
  // A 2D disk assembly is an in-plane elastic medium with the constants of
  // the plane-stress fit (E', nu'; docs/architecture.md, "Plane-stress and
  // plane-strain constants"): eps_x = (sigma_x - nu' sigma_y) / E'. Fixed
  // lateral walls (eps_x = 0) give d sigma_x / d sigma_y = nu', which is
  // nu / (1 - nu) of the plane-strain pair (nu = nu'/(1 + nu')), the 3D
  // closed form with the continuum's nu.
  const LabTestParams lu            = elastic_test(CompressionType::unconfined, 0);
  const LabTestParams lz            = elastic_test(CompressionType::uniaxial_strain, 1e6);
  const LabTestResult u             = run<2>(elastic(), box2d(), 250, lu);
  const LabTestResult z             = run<2>(elastic(), box2d(), 250, lz);
  const double        ratio         = lateral_to_axial_ratio(z, lz, false);
  const double        ratio_regions = lateral_to_axial_ratio(z, lz, true);
  INFO("nu' " << u.nu_ps << " nu " << u.nu << " -> nu/(1-nu) " << u.nu / (1 - u.nu)
              << "; measured ratio " << ratio << " (walls), " << ratio_regions
              << " (measurement regions), lateral gauge strain at the end "
              << z.history.back().lateral_strain << " vs axial "
              << z.history.back().gauge_axial_strain);
  REQUIRE(u.nu_ps > 0.05);
  CHECK(u.nu / (1 - u.nu) == Approx(u.nu_ps).epsilon(1e-12));
  // A 250-grain specimen is not an isotropic continuum: its fabric and the
  // grain layer along the fixed walls (the interior measurement regions give
  // 0.152) shift the wall ratio by about 12 % at 0.3/s (0.189 against
  // nu' = 0.216); 15 % still separates it from the free lateral expansion
  // (ratio 0) and from a fluid-like response (ratio 1).
  CHECK(ratio == Approx(u.nu_ps).epsilon(0.15));
  // Fixed walls: the specimen's own lateral strain stays near zero
  // (measured 0.9 % of the axial strain; the wall-grain contacts deform).
  CHECK(std::abs(z.history.back().lateral_strain) <
        0.02 * std::abs(z.history.back().gauge_axial_strain));
  CHECK(!(z.confining_deviation == z.confining_deviation)); // NaN: walls fixed
}

TEST_CASE("flexible lateral walls: tributary areas integrate the platen gap, the length "
          "is their weighted mean position",
          "[labtests][confined][flexible]")
{
  Walls<2>     w;
  VesselParams vp = box2d(); // expansion factor 1.2: 6 mm beyond each platen
  Vessel<2>    v  = make_vessel(w, vp);
  const int    n  = 6;
  v.make_flexible(w, 0, n, 1.0);
  REQUIRE(v.flexible(0));
  REQUIRE(!v.flexible(1));
  // n facets between the platens and one beyond each: n + 3 vertices.
  REQUIRE(v.hi_chain[0].size() == std::size_t(n + 3));
  REQUIRE(v.lo_chain[0].size() == std::size_t(n + 3));
  // Rounding only (sums of a few terms of 1e-2 m): 1e-14 m.
  CHECK(v.length(w, 0) == Approx(0.03).margin(1e-14));
  CHECK(v.area(w, 1) == Approx(0.03).margin(1e-14));
  // Straight chain between the platens: the end vertices carry nothing, the
  // platen vertices half a facet, the others a facet (H / n).
  auto A = v.tributary_areas(w, v.hi_chain[0]);
  CHECK(A.front() == 0);
  CHECK(A.back() == 0);
  CHECK(A[1] == Approx(0.005).margin(1e-15));
  for (int k = 2; k <= n; ++k)
    CHECK(A[k] == Approx(0.01).margin(1e-15));
  CHECK(std::accumulate(A.begin(), A.end(), 0.0) == Approx(0.06).margin(1e-15));
  // The rigid walls are parked 1 m outward (their contacts end).
  CHECK(w.vertex[v.hi_vertex[0]][0] == Approx(0.015).margin(1e-15));
  for (std::size_t k = 0; k < w.n_facets(); ++k)
    if (w.wall_name[w.facet_wall[k]] == "x+")
      for (int j : w.facet[k])
        CHECK(w.vertex[j][0] == Approx(1.015).margin(1e-12));

  // Platens moved in by 2 mm each: the gap is 56 mm and the platen vertex
  // (y = 30 mm, its hat from 20 to 40 mm) keeps the part of its hat below
  // 28 mm: (8 mm)^2 / (2 x 10 mm) = 3.2 mm.
  v.translate_outward(w, 1, -0.002);
  A = v.tributary_areas(w, v.hi_chain[0]);
  CHECK(std::accumulate(A.begin(), A.end(), 0.0) == Approx(0.056).margin(1e-15));
  CHECK(A[n + 1] == Approx(0.0032).margin(1e-15));
  CHECK(A[n + 2] == 0);

  // One vertex bulged out by 1 mm: the length grows by 1 mm x its share of
  // the gap (10 / 56).
  w.vertex[v.hi_chain[0][3]][0] += 0.001;
  CHECK(v.length(w, 0) == Approx(0.03 + 0.001 * 0.01 / 0.056).margin(1e-14));

  // A velocity for the whole axis moves every vertex of both chains.
  v.set_velocity(w, 0, 0.25);
  for (int j : v.hi_chain[0])
    CHECK(w.vertex_velocity[j][0] == 0.25);
  for (int j : v.lo_chain[0])
    CHECK(w.vertex_velocity[j][0] == -0.25);
}

TEST_CASE("flexible lateral walls: each vertex holds Pc, the moduli are the unconfined "
          "ones (2D, elastic)",
          "[labtests][confined][flexible]")
{
  // Linear elasticity: with sigma_3 held, d sigma_1 = E d eps_1 and
  // d eps_3 = -nu d eps_1 whatever the confinement (as above).
  // Elastic specimen (strengths 1e15 Pa) confined at 2 MPa by 4 facets per
  // wall (15 mm, about 11 grains, each).
  const double        Pc   = 2e6;
  Specimen<2>         flex = make_specimen<2>(elastic(), box2d(), 250);
  const LabTestResult f    = run_lab_test(flex, flexible_test(Pc, 4));
  const LabTestResult u =
      run<2>(elastic(), box2d(), 250, elastic_test(CompressionType::unconfined, 0));
  INFO("unconfined: E' " << u.E_ps << " nu' " << u.nu_ps << "; flexible: E' " << f.E_ps
                         << " nu' " << f.nu_ps << " deviation " << f.confining_deviation);
  CHECK(f.lateral_wall_segments == 4);
  REQUIRE(f.E_ps > 0);
  // Measured E' 26.10 against 26.36 GPa (-1.0 %), nu' 0.213 against 0.216.
  // Rigid walls read nu' 0.236 here (the test above allows them 0.025):
  // they impose one lateral displacement on the outermost grains of a
  // 250-grain specimen, where the flexible wall imposes the pressure. 2 %
  // and 0.01: the same specimen and packing, a different boundary.
  CHECK(f.E_ps == Approx(u.E_ps).epsilon(0.02));
  CHECK(f.nu_ps == Approx(u.nu_ps).margin(0.01));
  // Measured 0.03 % (rigid walls 0.05 %).
  CHECK(f.confining_deviation < 0.01);
  // Every vertex between the platens at the last step: its own force over
  // its tributary area is Pc. Measured within 0.005 %: elastic and slow,
  // the integral term has learnt each vertex's velocity; 0.5 %.
  const auto &W = flex.model.walls;
  for (int s = 0; s < 2; ++s)
    {
      const auto &chain = s ? flex.vessel.hi_chain[0] : flex.vessel.lo_chain[0];
      const auto  A     = flex.vessel.tributary_areas(W, chain);
      for (std::size_t k = 0; k < chain.size(); ++k)
        if (A[k] > 0.5 * 0.015) // a whole hat between the platens
          {
            const double P = (s ? 1 : -1) * W.vertex_force[chain[k]][0] / A[k];
            INFO("wall " << s << " vertex " << k << ": " << P << " Pa");
            CHECK(P == Approx(Pc).epsilon(0.005));
          }
    }
}

TEST_CASE("flexible lateral walls hold Pc up to the peak (2D, breakable)",
          "[labtests][confined][flexible]")
{
  // The breakable specimen of the rigid walls' test above (tensile strength
  // 20 +- 6 MPa, cohesion 60 MPa) at 5 MPa, to the post-peak end.
  const double        Pc = 5e6;
  LabTestParams       l  = flexible_breakable_test(Pc);
  const LabTestResult r  = run<2>(material(20e6, 6e6, 60e6), box2d(), 250, l);
  INFO("peak " << r.peak << " Pa, ended by " << r.ended_by << ", Pc deviation to peak "
               << r.confining_deviation_to_peak << ", spike "
               << r.confining_spike_to_peak);
  REQUIRE(r.ended_by == "post-peak");
  CHECK(r.peak > 3 * Pc);
  // Averaged over a wave's crossing time, as for the rigid walls
  // (above); measured 0.76 % (rigid walls 0.74 %).
  CHECK(r.confining_deviation_to_peak < 0.01);
  CHECK(r.crack_initiation < r.peak);
}

TEST_CASE("flexible lateral walls: the confined result does not depend on the time step "
          "(2D, breakable)",
          "[labtests][confined][flexible]")
{
  // The test above at time-step safety 0.8 and 0.4 (Tests/time step
  // safety): the vertex servos' gains are per step (alpha A / (sum w k_n
  // dt)) and the deviation is averaged over physical time, so halving the
  // step must leave Pc held and the peak within the chaotic scatter of one
  // packing's trajectories (the unconfined test's bound in
  // lab_tests_test.cc: 2 %).
  const double  Pc = 5e6;
  LabTestParams l  = flexible_breakable_test(Pc);
  LabTestResult r[2];
  const double  safety[2] = {0.8, 0.4};
  for (int k = 0; k < 2; ++k)
    {
      l.timestep_safety = safety[k];
      r[k]              = run<2>(material(20e6, 6e6, 60e6), box2d(), 250, l);
    }
  INFO("peak " << r[0].peak << " Pa (safety 0.8), " << r[1].peak
               << " Pa (0.4); Pc deviation to peak " << r[0].confining_deviation_to_peak
               << ", " << r[1].confining_deviation_to_peak << "; E " << r[0].E << ", "
               << r[1].E);
  REQUIRE(r[0].ended_by == "post-peak");
  REQUIRE(r[1].ended_by == "post-peak");
  // Measured: Pc deviation to the peak 0.76 % / 0.27 %, peak +0.77 %
  // (77.5 / 78.1 MPa), E the same to 1e-5 (the unconfined test's bound:
  // 0.5 %).
  CHECK(r[0].confining_deviation_to_peak < 0.01);
  CHECK(r[1].confining_deviation_to_peak < 0.01);
  CHECK(r[1].peak == Approx(r[0].peak).epsilon(0.02));
  CHECK(r[1].E == Approx(r[0].E).epsilon(0.005));
}

TEST_CASE("pressure boundary: the moduli are the unconfined ones, the mid-section "
          "carries Pc H (2D, elastic)",
          "[labtests][confined][pressure]")
{
  // As for the flexible walls above: with sigma_3 held, E and nu are the
  // unconfined ones in the elastic range. P_c now acts on the outermost
  // grains themselves (dem/specimen/pressure_boundary.h), so the boundary's
  // pressure is P_c to round-off, and the specimen must carry it: after
  // the seating, the contacts crossing the vertical mid-section x = 0
  // transmit P_c H horizontally (the platens are frictionless here: the
  // grain-wall contacts' friction is 0).
  const double  Pc    = 2e6;
  LabTestParams l     = elastic_test(CompressionType::confined, Pc);
  l.pressure_boundary = true;
  Specimen<2>     s   = make_specimen<2>(elastic(), box2d(), 250);
  double          H = 0, transmitted = 0;
  LabCallbacks<2> cb;
  cb.progress = [&](const LabProgress &g) {
    if (H > 0 || std::string(g.phase) != "compression")
      return;
    const auto &m = s.model;
    H             = s.vessel.length(m.walls, 1);
    for (int gi = 0; gi < m.n_groups(); ++gi)
      {
        const auto &grp = m.group(gi);
        for (std::size_t k = 0; k < grp.size(); ++k)
          {
            const auto &x1 = m.particles.x[grp.end1[k]];
            if (!grp.active(k) || grp.is_wall[k])
              continue;
            const auto &x2 = m.particles.x[grp.end2[k]];
            if ((x1[0] < 0) != (x2[0] < 0)) // pushes the right-hand grain right
              transmitted += (x2[0] > x1[0] ? 1 : -1) * grp.force[k][0];
          }
      }
  };
  const LabTestResult r = run_lab_test(s, l, cb);
  const LabTestResult u =
      run<2>(elastic(), box2d(), 250, elastic_test(CompressionType::unconfined, 0));
  INFO("unconfined: E' " << u.E_ps << " nu' " << u.nu_ps << "; pressure boundary: E' "
                         << r.E_ps << " nu' " << r.nu_ps << " deviation "
                         << r.confining_deviation << "; mid-section " << transmitted
                         << " N/m for Pc H " << Pc * H);
  CHECK(r.confining_boundary == "pressure");
  CHECK(r.lateral_wall_segments == 0);
  REQUIRE(r.E_ps > 0);
  // Measured E' 26.28 against 26.36 GPa (-0.3 %), nu' 0.2151 against
  // 0.2158: the flexible walls' bounds (same specimen and packing,
  // another boundary).
  CHECK(r.E_ps == Approx(u.E_ps).epsilon(0.02));
  CHECK(r.nu_ps == Approx(u.nu_ps).margin(0.01));
  // By construction, to round-off.
  CHECK(r.confining_deviation < 1e-9);
  CHECK(r.history.back().lateral_wall_stress == Approx(-Pc).epsilon(1e-9));
  // Static equilibrium of either half: measured 0.09 % off (the seating
  // ends at an unbalanced-force ratio of 1e-4, not at rest); 0.5 %.
  REQUIRE(H > 0);
  CHECK(transmitted == Approx(Pc * H).epsilon(0.005));
}

TEST_CASE("pressure boundary: to the post-peak end, independent of the time step (2D, "
          "breakable)",
          "[labtests][confined][pressure]")
{
  // The flexible walls' breakable test at 5 MPa with the pressure boundary,
  // at time-step safety 0.8 and 0.4: the forces are set from the grains'
  // positions every step, with nothing per step to tune. E must agree
  // within 0.5 % (the unconfined test's bound; measured 3e-4). The peak
  // takes one of two values, 74.7 or 77.1-77.6 MPa (3.8 % apart), as
  // numerical details change: safety 0.8 to 0.3 read 77.6, 77.1, 77.1,
  // 75.3, 74.7, 75.3 MPa; at safety 0.8 the rays' spacing (0.15, 0.2, 0.25,
  // 0.3 of the smallest radius) reads 77.6, 74.7, 77.6, 77.0; at half the
  // rate safety 0.8 / 0.6 / 0.4 read 77.5 / 77.1 / 74.7: two failure paths
  // of this 250-grain specimen, not a trend with the step (the flexible
  // walls' peaks stay within 1 % here: 77.5-78.3). Hence 4 %, the gap
  // between the two paths (docs/calibrate.md, "Confining boundary").
  const double  Pc    = 5e6;
  LabTestParams l     = flexible_breakable_test(Pc);
  l.lateral_segments  = 1;
  l.pressure_boundary = true;
  LabTestResult r[2];
  const double  safety[2] = {0.8, 0.4};
  for (int k = 0; k < 2; ++k)
    {
      l.timestep_safety = safety[k];
      r[k]              = run<2>(material(20e6, 6e6, 60e6), box2d(), 250, l);
    }
  INFO("peak " << r[0].peak << " Pa (safety 0.8), " << r[1].peak << " Pa (0.4); E "
               << r[0].E << ", " << r[1].E << "; crack initiation "
               << r[0].crack_initiation);
  for (int k = 0; k < 2; ++k)
    {
      REQUIRE(r[k].ended_by == "post-peak");
      CHECK(r[k].peak > 3 * Pc);
      CHECK(r[k].confining_deviation < 1e-9);
      CHECK(r[k].crack_initiation < r[k].peak);
    }
  CHECK(r[1].peak == Approx(r[0].peak).epsilon(0.04));
  CHECK(r[1].E == Approx(r[0].E).epsilon(0.005));
}

TEST_CASE("pressure boundary: refused in 3D and with flexible walls, naming the key",
          "[labtests][confined][pressure]")
{
  LabTestParams l     = elastic_test(CompressionType::confined, 1e6);
  l.pressure_boundary = true;
  CHECK_NOTHROW(l.validate("test.prm", 2, "Tests/"));
  CHECK_THROWS_WITH(l.validate("test.prm", 3, "Tests/"),
                    Catch::Contains("Tests/confining boundary = pressure") &&
                        Catch::Contains("allowed in 3D: walls"));
  l.lateral_segments = 4;
  CHECK_THROWS_WITH(l.validate("test.prm", 2, "Tests/"),
                    Catch::Contains("Tests/lateral wall segments = 4") &&
                        Catch::Contains("confining boundary = pressure: 1"));
}

TEST_CASE("flexible lateral walls: bad segment counts are refused naming the key",
          "[labtests][confined][flexible]")
{
  LabTestParams l = flexible_test(1e6, 2);
  CHECK_NOTHROW(l.validate("test.prm", 2, "Tests/"));
  CHECK_THROWS_WITH(l.validate("test.prm", 3, "Tests/"),
                    Catch::Contains("Tests/lateral wall segments = 2") &&
                        Catch::Contains("allowed in 3D: 1"));
  l.lateral_segments = 0;
  CHECK_THROWS_WITH(l.validate("test.prm", 2, "Tests/"),
                    Catch::Contains("Tests/lateral wall segments"));
  // 60 mm / 40 = 1.5 mm facets: below two grain diameters (2.66 mm).
  l.lateral_segments = 40;
  Specimen<2> s      = make_specimen<2>(elastic(), box2d(), 250);
  CHECK_THROWS_WITH(run_lab_test(s, l), Catch::Contains("lateral wall segments = 40") &&
                                            Catch::Contains("allowed for this specimen"));
}
