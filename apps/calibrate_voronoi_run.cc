// The run of `demfem calibrate` for Voronoi grains (calibrate_voronoi.h):
// the specimens are packed and tessellated once, every test runs on a fresh
// model of them (dem/voronoi/voronoi_lab_test.h), and the outputs follow the
// bonded-particle material types (docs/calibrate.md): material.json,
// summary.json with the run status, history_<test>.csv,
// <test>_stress_strain.svg and VTK of the cells (flexible grains: their
// element triangles), contact points and cracks at the end of each test.
#include "apps/calibrate_output.h"
#include "apps/calibrate_voronoi.h"
#include "dem/io/vtk_output.h"
#include "dem/specimen/crack_initiation.h"
#include "dem/specimen/envelope.h"
#include "dem/voronoi/voronoi_vtk.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

namespace demfem::apps
{
  namespace
  {
    namespace fs  = std::filesystem;
    namespace vor = dem::voronoi;
    using Clock   = std::chrono::steady_clock;

    // The largest centre distance of two neighbouring grains: the contact
    // whose brittle fracture energies (sigma_t^2 d / (2 E_c), c^2 kappa d /
    // (2 E_c); docs/voronoi.md, "Contact stiffness") are the largest.
    double largest_contact_length(const vor::VoronoiSpecimen &sp)
    {
      const auto &t = sp.tessellation;
      double      d = 0;
      for (int c = 0; c < t.n_cells(); ++c)
        for (int e = t.begin(c); e < t.end(c); ++e)
          if (const int n = t.edge_neighbour[e]; n > c)
            d = std::max(d, std::hypot(sp.x[n] - sp.x[c], sp.y[n] - sp.y[c]));
      return d;
    }

    void check_fracture_energies(const VoronoiCalibrateSettings &s,
                                 const vor::VoronoiSpecimen     &sp)
    {
      const auto  &c     = s.contact;
      const double d     = largest_contact_length(sp);
      auto         check = [&](const char *key, double G, double brittle) {
        if (G > 0 && G < brittle * (1 - 1e-9))
          {
            std::ostringstream m;
            m << s.where << ": Material/Voronoi/" << key << " = " << G
              << " J/m^2 is below the brittle value " << brittle
              << " J/m^2 of the longest contact of the packing (d = " << d
              << " m); a smaller energy would need a snap-back (allowed: 0 for the "
                         "brittle value of each contact, or >= "
              << brittle << ")";
            throw dem::InputError(m.str());
          }
      };
      check("tensile fracture energy", c.tensile_fracture_energy,
            c.tensile_strength * c.tensile_strength * d / (2 * c.contact_modulus));
      check("shear fracture energy", c.shear_fracture_energy,
            c.cohesion * c.cohesion * c.kratio * d / (2 * c.contact_modulus));
    }

    std::string history_csv(const std::vector<vor::VoronoiLabRow> &h)
    {
      std::ostringstream o;
      o.precision(10);
      o << "step,time_s,axial_strain,lateral_strain,axial_stress_Pa,load_Pa,"
           "cracks_tensile,cracks_shear\n";
      for (const auto &r : h)
        o << r.step << ',' << r.time << ',' << r.axial_strain << ',' << r.lateral_strain
          << ',' << r.axial_stress << ',' << r.load << ',' << r.cracks_tensile << ','
          << r.cracks_shear << '\n';
      return o.str();
    }

    Json microparameters(const VoronoiCalibrateSettings &s)
    {
      const auto &c = s.contact;
      const auto &p = s.specimen;
      Json        j;
      j.str("type", s.flexible ? "flexible-voronoi" : "rigid-voronoi")
          .num("contact_modulus_Pa", c.contact_modulus)
          .num("stiffness_ratio", c.kratio)
          .num("tensile_strength_Pa", c.tensile_strength)
          .num("cohesion_Pa", c.cohesion)
          .num("friction", c.friction)
          .num("tensile_fracture_energy_J_m2", c.tensile_fracture_energy)
          .num("shear_fracture_energy_J_m2", c.shear_fracture_energy)
          .str("fracture_energy_zero_means", "the brittle value of each contact")
          .str("contact_points",
               s.lab.scheme == vor::PointScheme::lobatto3 ? "lobatto" : "reference point")
          .num("thickness_m", c.thickness)
          .num("density_kg_m3", s.density);
      if (s.flexible)
        j.num("grain_youngs_modulus_Pa", s.grain.youngs_modulus)
            .num("grain_poisson_ratio", s.grain.poisson_ratio)
            .str("grain_elasticity", "plane strain (Saint Venant-Kirchhoff CST)");
      j.num("local_damping", s.lab.damping)
          .num("time_step_safety", s.lab.safety)
          .num("seed", double(p.seed))
          .num("n_grains_requested", p.n_grains)
          .num("D_lo_m", p.d_min)
          .num("D_hi_m", p.d_max)
          .num("packing_pressure_Pa", p.packing_pressure)
          .num("packing_modulus_Pa", p.packing_modulus)
          .num("vessel_H_m", p.height)
          .num("vessel_W_m", p.width);
      return j;
    }

    Json result_json(const vor::VoronoiLabResult &r)
    {
      Json j;
      j.str("ended_by", r.ended_by)
          .str("status",
               r.status == vor::VoronoiLabStatus::ok ? "ok" : "step_limit_reached")
          .num("confining_steps", double(r.confining_steps))
          .num("loading_steps", double(r.loading_steps))
          .num("time_step_s", r.time_step)
          .num("final_time_step_s", r.final_time_step)
          .num("contacts_formed", r.new_contacts)
          .num("peak_Pa", r.peak_stress)
          .num("peak_load_Pa", r.peak_load)
          .num("peak_strain", r.peak_strain)
          .num("cracks_tensile_at_peak", r.cracks_tensile_peak)
          .num("cracks_shear_at_peak", r.cracks_shear_peak)
          .num("cracks_tensile_at_end", r.cracks_tensile)
          .num("cracks_shear_at_end", r.cracks_shear)
          .num("n_grains", r.n_grains)
          .num("n_contacts", r.n_contacts)
          .num("n_points", r.n_points);
      if (r.peak_force > 0)
        j.num("peak_force_N", r.peak_force);
      else
        j.num("E_plane_stress_Pa", r.E).num("nu_plane_stress", r.nu);
      return j;
    }
  } // namespace

  double voronoi_crack_initiation(const vor::VoronoiLabResult    &r,
                                  const VoronoiCalibrateSettings &s,
                                  dem::CrackInitiationMethod method, bool compression)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (method != dem::CrackInitiationMethod::crack_count && compression)
      {
        // Tension positive; the 2D slopes E = d sigma_a / d eps_a and
        // nu = -d eps_l / d eps_a of the loading branch (one lateral
        // direction).
        dem::CompressionBranch b;
        double                 largest = -1;
        for (std::size_t i = 0; i < r.history.size(); ++i)
          {
            const auto &h = r.history[i];
            b.volumetric_strain.push_back(h.axial_strain + h.lateral_strain);
            b.lateral_strain.push_back(h.lateral_strain);
            b.axial_stress.push_back(h.axial_stress);
            b.load.push_back(h.load);
            if (h.load > largest)
              largest = h.load, b.peak_row = i;
          }
        const std::size_t row =
            method == dem::CrackInitiationMethod::volumetric_strain
                ? dem::crack_volumetric_initiation_row(b, r.E, r.nu, 1, s.lab.fit_lo,
                                                       s.lab.fit_hi,
                                                       s.crack_volumetric_fraction)
                : dem::lateral_strain_initiation_row(b, dem::volumetric_reversal_row(b));
        return row < r.history.size() ? std::abs(r.history[row].axial_stress) : nan;
      }
    const double at_peak = r.cracks_tensile_peak + r.cracks_shear_peak;
    if (!(at_peak > 0))
      return nan;
    for (const auto &h : r.history)
      if (h.cracks_tensile + h.cracks_shear >= s.crack_initiation_fraction * at_peak)
        return std::abs(h.axial_stress);
    return nan;
  }

  PlaneStrainConstants plane_strain_constants(double E_2d, double nu_2d)
  {
    // The library's E, nu are the 2D constants of the free-sided specimen
    // (E' = d sigma / d eps_a, nu' = -d eps_r / d eps_a), the pair fistPkg
    // Eq. 19 gives for disks; the continuum gets the plane-strain pair as
    // for the bonded materials (docs/architecture.md): nu = nu'/(1+nu'),
    // E = E'(1-nu^2). Flexible grains are plane-strain elements, so this
    // reading is theirs too.
    const double nu = nu_2d / (1 + nu_2d);
    return {E_2d * (1 - nu * nu), nu};
  }

  vor::VoronoiLabResult run_voronoi_test(const VoronoiCalibrateSettings &s,
                                         const VoronoiSpecimens         &sp,
                                         const VoronoiTestSpec          &t,
                                         const std::string              &vtk_base)
  {
    vor::VoronoiLabParams lp = s.lab;
    lp.test                  = t.test;
    lp.confining_pressure    = t.confining_pressure;
    const bool brazilian     = t.test == vor::VoronoiTest::brazilian;
    lp.platen_friction       = brazilian ? s.brazilian_platen_friction : 0.0;
    const auto &specimen     = brazilian ? sp.disk : sp.rectangle;
    const bool  vtk          = !vtk_base.empty();
    // The same three files for either kind of grain (dem/voronoi/voronoi_vtk.h).
    auto write = [&](const auto &model, auto &&write_cells) {
      write_cells(vtk_base + "cells.vtp");
      vor::write_voronoi_points_vtk(vtk_base + "points.vtp", model);
      vor::write_voronoi_cracks_vtk(vtk_base + "cracks.vtp", model);
    };
    if (s.flexible)
      {
        std::optional<vor::FlexibleVoronoiModel> model;
        const auto r = vor::run_flexible_voronoi_lab_test(specimen, s.contact, s.grain,
                                                          lp, vtk ? &model : nullptr);
        if (vtk && model)
          write(*model, [&](const std::string &path) {
            vor::write_voronoi_cells_vtk(path, *model);
          });
        return r;
      }
    std::optional<vor::RigidVoronoiModel> model;
    const auto r = vor::run_voronoi_lab_test(specimen, s.contact, s.density, lp,
                                             vtk ? &model : nullptr);
    if (vtk && model)
      write(*model, [&](const std::string &path) {
        vor::write_voronoi_cells_vtk(path, specimen.tessellation, *model);
      });
    return r;
  }

  VoronoiSpecimens make_voronoi_specimens(const VoronoiCalibrateSettings &s)
  {
    const auto       t0 = Clock::now();
    VoronoiSpecimens sp;
    std::cerr << "demfem calibrate: packing and tessellating "
              << (s.flexible ? "flexible" : "rigid") << " Voronoi grains\n";
    sp.rectangle = vor::make_voronoi_specimen(s.specimen);
    check_fracture_energies(s, sp.rectangle);
    const bool brazilian =
        std::any_of(s.tests.begin(), s.tests.end(), [](const VoronoiTestSpec &t) {
          return t.test == vor::VoronoiTest::brazilian;
        });
    if (brazilian)
      {
        // The disk of diameter min(W, H) (as the bonded materials' Brazilian
        // test, docs/calibrate.md), packed with the rectangle's grain size.
        vor::VoronoiSpecimenParams d = s.specimen;
        const double               D = std::min(d.width, d.height);
        d.n_grains *= D * D / (d.width * d.height);
        d.width = d.height = D;
        sp.disk            = vor::make_voronoi_disk_specimen(d);
        sp.has_disk        = true;
        check_fracture_energies(s, sp.disk);
      }
    sp.genesis_s = seconds_since(t0);
    return sp;
  }

  CalibrateOutcome run_voronoi_calibration(const VoronoiCalibrateSettings &s,
                                           const VoronoiSpecimens         &sp)
  {
    const auto t_start = Clock::now();
    fs::create_directories(s.out);
    const std::string vtk_dir = s.out + "/vtk";
    const bool        vtk     = s.vtk;
    if (vtk)
      fs::create_directories(vtk_dir);
    const std::string kind = s.flexible ? "flexible-voronoi" : "rigid-voronoi";

    std::vector<std::string>                                   truncated;
    std::vector<std::pair<std::string, vor::VoronoiLabResult>> results;
    Json                                                       tests_json;
    for (const auto &t : s.tests)
      {
        const bool brazilian = t.test == vor::VoronoiTest::brazilian;
        const auto name      = file_name(t.label);
        std::cerr << "demfem calibrate: " << t.label << " (" << kind << ")\n";
        const auto                  t_test = Clock::now();
        const vor::VoronoiLabResult r =
            run_voronoi_test(s, sp, t, vtk ? vtk_dir + "/" + name + "_end_" : "");
        const double test_s = seconds_since(t_test);
        dem::vtkout::write_text_atomically(s.out + "/history_" + name + ".csv",
                                           history_csv(r.history));
        const bool compression = t.test != vor::VoronoiTest::direct_tension &&
                                 t.test != vor::VoronoiTest::brazilian;
        // Compression positive for compression and Brazilian, tension
        // positive for direct tension (as the bonded materials' plots).
        const double        sign = t.test == vor::VoronoiTest::direct_tension ? 1 : -1;
        std::vector<double> x, y;
        for (const auto &h : r.history)
          x.push_back(100 * sign * h.axial_strain),
              y.push_back(sign * h.axial_stress / 1e6);
        dem::vtkout::write_text_atomically(
            s.out + "/" + name + "_stress_strain.svg",
            svg_plot(
                t.label + " (2D " + kind + ", " + std::to_string(r.n_grains) + " grains)",
                "axial strain [%]",
                brazilian ? "F / (2 R t)  [MPa]" : "axial stress (platens) [MPa]", x, y));
        Json j = result_json(r);
        j.num("run_time_s", test_s)
            .num("strain_rate_1_s", s.lab.strain_rate)
            .num("Pc_Pa", t.confining_pressure)
            .num("platen_friction", brazilian ? s.brazilian_platen_friction : 0.0)
            .num("crack_initiation_Pa",
                 voronoi_crack_initiation(r, s, s.crack_initiation_method, compression))
            .num("crack_initiation_crack_count_Pa",
                 voronoi_crack_initiation(r, s, dem::CrackInitiationMethod::crack_count,
                                          compression))
            .num("crack_initiation_volumetric_Pa",
                 compression
                     ? voronoi_crack_initiation(
                           r, s, dem::CrackInitiationMethod::volumetric_strain, true)
                     : std::numeric_limits<double>::quiet_NaN())
            .num("crack_initiation_lateral_Pa",
                 compression ? voronoi_crack_initiation(
                                   r, s, dem::CrackInitiationMethod::lateral_strain, true)
                             : std::numeric_limits<double>::quiet_NaN());
        tests_json.obj(name, j);
        std::cerr << "demfem calibrate: " << t.label << ": peak " << r.peak_stress / 1e6
                  << " MPa (" << r.ended_by << ", " << r.loading_steps << " steps, "
                  << test_s << " s)\n";
        if (r.status == vor::VoronoiLabStatus::step_limit_reached)
          {
            truncated.push_back(t.label);
            std::cerr << "demfem calibrate: warning: " << t.label
                      << " ended at Tests/step limit (" << r.loading_steps
                      << " steps) before its post-peak end: its peak may not be "
                         "reached; raise Tests/step limit\n";
          }
        results.emplace_back(t.label, r);
      }

    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto         get = [&](const std::string &label) -> const vor::VoronoiLabResult         *{
      for (const auto &[l, r] : results)
        if (l == label)
          return &r;
      return nullptr;
    };
    const vor::VoronoiLabResult *ucs =
        get("ucs") ? get("ucs") : get("triaxial series 0 MPa");
    const vor::VoronoiLabResult *el   = ucs ? ucs : get("triaxial");
    const vor::VoronoiLabResult *dt   = get("direct tension");
    const vor::VoronoiLabResult *bts  = get("brazilian");
    const double                 Eps  = el ? el->E : nan;
    const double                 nups = el ? el->nu : nan;
    const auto [E, nu]                = plane_strain_constants(Eps, nups);
    auto peak  = [&](const vor::VoronoiLabResult *r) { return r ? r->peak_stress : nan; };
    auto ratio = [&](double a, double b) { return b > 0 ? a / b : nan; };
    auto ci_by = [&](dem::CrackInitiationMethod m) {
      return el ? voronoi_crack_initiation(*el, s, m, true) : nan;
    };
    const double ci          = ci_by(s.crack_initiation_method);
    double       triaxial_pc = nan;
    for (const auto &t : s.tests)
      if (t.label == "triaxial")
        triaxial_pc = t.confining_pressure;

    // Post-peak brittleness of the unconfined test (calibrate_output.h).
    auto post_peak = [](const vor::VoronoiLabResult &r) {
      std::vector<double> e, q;
      for (const auto &h : r.history)
        e.push_back(h.axial_strain), q.push_back(h.axial_stress);
      return post_peak_strain_ratio(e, q);
    };
    Json mat;
    mat.num("dim", 2)
        .str("material_type", kind)
        .num("n_grains", sp.rectangle.tessellation.n_cells() -
                             double(sp.rectangle.tessellation.empty_cells.size()))
        .num("porosity", 0)
        .num("E", E)
        .num("nu", nu)
        .num("E_plane_stress", Eps)
        .num("nu_plane_stress", nups)
        .num("ucs", peak(ucs))
        .num("triaxial_strength", peak(get("triaxial")))
        .num("confining_pressure", triaxial_pc)
        .num("bts", peak(bts))
        .num("direct_tension", peak(dt))
        .num("crack_initiation", ci)
        .str("crack_initiation_method",
             dem::crack_initiation_method_name(s.crack_initiation_method))
        .num("crack_initiation_crack_count",
             ci_by(dem::CrackInitiationMethod::crack_count))
        .num("crack_initiation_volumetric",
             ci_by(dem::CrackInitiationMethod::volumetric_strain))
        .num("crack_initiation_lateral",
             ci_by(dem::CrackInitiationMethod::lateral_strain));
    Json ratios;
    ratios.num("crack_initiation_to_ucs", ratio(ci, peak(ucs)))
        .num("direct_tension_to_bts", ratio(peak(dt), peak(bts)))
        .num("ucs_to_bts", ratio(peak(ucs), peak(bts)))
        .num("ucs_to_direct_tension", ratio(peak(ucs), peak(dt)))
        .num("post_peak_strain_ratio", ucs ? post_peak(*ucs) : nan);
    mat.obj("ratios", ratios);
    // Triaxial series: the peaks and, with two or more pressures, the
    // Mohr-Coulomb and Hoek-Brown fits (dem/specimen/envelope.h).
    std::vector<double> s3, s1;
    for (const auto &t : s.tests)
      if (t.in_series)
        s3.push_back(t.confining_pressure), s1.push_back(get(t.label)->peak_stress);
    if (s3.size() >= 2)
      {
        StrengthEnvelope env;
        env.sigma_3 = s3;
        env.sigma_1 = s1;
        Json e;
        try
          {
            env.fit(s.where);
            e = env.json();
          }
        catch (const std::invalid_argument &error)
          {
            // Peaks that no envelope fits (e.g. a test stopped at the strain
            // limit below sigma_3): the peaks are kept, the fit is not.
            std::cerr << "demfem calibrate: warning: no envelope fitted: " << error.what()
                      << "\n";
            e.nums("confining_pressures_Pa", s3).nums("peak_axial_stresses_Pa", s1);
            e.str("fit_error", error.what());
          }
        mat.obj("envelope", e);
      }
    Json units;
    for (const char *k :
         {"E", "E_plane_stress", "ucs", "triaxial_strength", "confining_pressure", "bts",
          "direct_tension", "crack_initiation", "crack_initiation_crack_count",
          "crack_initiation_volumetric", "crack_initiation_lateral"})
      units.str(k, "Pa");
    units.str("nu", "1")
        .str("nu_plane_stress", "1")
        .str("porosity", "1")
        .str("n_grains", "1");
    mat.obj("units", units);
    mat.str("elastic_constants",
            "E, nu: plane-strain pair for the continuum (docs/architecture.md: nu = "
            "nu'/(1+nu'), E = E'(1-nu^2)) from the 2D constants E', nu' of the "
            "free-sided Voronoi specimen (E_plane_stress, nu_plane_stress)");
    mat.str("porosity_note", "Voronoi cells tile the specimen: no pore space");
    mat.str("fit_window", "least squares between " + std::to_string(s.lab.fit_lo) +
                              " and " + std::to_string(s.lab.fit_hi) +
                              " of the peak load");
    mat.obj("microparameters", microparameters(s));
    dem::vtkout::write_text_atomically(s.out + "/material.json", mat.text() + "\n");

    Json sum;
    sum.str("command", "calibrate")
        .str("status", truncated.empty() ? "ok" : "step_limit_reached")
        .str("parameter_file", s.where)
        .str("material_type", kind)
        .num("dim", 2)
        .num("genesis_s", sp.genesis_s)
        .num("wall_time_s", seconds_since(t_start))
        .str("vtk", vtk ? (s.flexible ? "vtk/<test>_end_{cells,points,cracks}.vtp "
                                        "(cells: the grains' element triangles)"
                                      : "vtk/<test>_end_{cells,points,cracks}.vtp")
                        : "off");
    sum.obj("tests", tests_json);
    dem::vtkout::write_text_atomically(s.out + "/summary.json", sum.text() + "\n");
    return calibration_outcome(s.out, seconds_since(t_start), truncated.size());
  }
} // namespace demfem::apps
