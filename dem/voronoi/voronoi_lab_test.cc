// Laboratory tests on rigid or flexible Voronoi grains
// (dem/voronoi/voronoi_lab_test.h).
#include "dem/voronoi/voronoi_lab_test.h"

#include "dem/voronoi/stable_time_step.h"

#include "dem/specimen/genesis.h"
#include "dem/specimen/lab_tests.h"
#include "dem/specimen/post_peak_end.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <string>

namespace demfem::dem::voronoi
{
  VoronoiSpecimen make_voronoi_specimen(const VoronoiSpecimenParams &p)
  {
    const std::string where = "Voronoi specimen";
    check_range(where, "width", p.width, 0, HUGE_VAL, true, true);
    check_range(where, "height", p.height, 0, HUGE_VAL, true, true);
    check_range(where, "d_min", p.d_min, 0, HUGE_VAL, true, true);
    check_range(where, "d_max", p.d_max, p.d_min, HUGE_VAL, false, true);
    check_range(where, "n_grains", p.n_grains, 4, HUGE_VAL, false, true);
    // The existing genesis (fistPkg §4.2.1 grain scaling) with a linear,
    // frictionless material: a dense isotropic packing whose disks are the
    // Laguerre weights (seed 004 §2.3).
    MaterialParams m;
    m.type     = "linear";
    m.sizes    = {SizePiece{false, p.d_min, p.d_max, 0, 0, 1.0}};
    m.lnm_emod = p.packing_modulus;
    m.lnm_krat = 1;
    m.lnm_fric = 0;
    m.Pm       = p.packing_pressure;
    m.seed     = p.seed;
    VesselParams v;
    v.W = p.width;
    v.H = p.height;
    v.D = 1;
    set_grain_count<2>(m, v, p.n_grains);
    Specimen<2> s = build_specimen<2>(m, v, nullptr, where);

    VoronoiSpecimen out;
    const auto     &P = s.model.particles;
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        out.x.push_back(P.x[i][0]);
        out.y.push_back(P.x[i][1]);
        out.radius.push_back(P.radius[i]);
      }
    const auto &W   = s.model.walls;
    const auto &ves = s.vessel;
    out.domain      = ClipDomain::rectangle(
             W.vertex[ves.lo_vertex[0]][0], W.vertex[ves.lo_vertex[1]][1],
             W.vertex[ves.hi_vertex[0]][0], W.vertex[ves.hi_vertex[1]][1]);
    out.tessellation = laguerre_tessellation(out.x, out.y, out.radius, out.domain);
    return out;
  }

  VoronoiSpecimen make_voronoi_disk_specimen(const VoronoiSpecimenParams &p, int sides)
  {
    // The rectangular packing, its disks with centres inside the circle
    // inscribed in it (a centre outside would own a cell that is not
    // around it), clipped to the circle.
    const VoronoiSpecimen box = make_voronoi_specimen(p);
    const double          cx  = 0.5 * (box.domain.xmin + box.domain.xmax);
    const double          cy  = 0.5 * (box.domain.ymin + box.domain.ymax);
    const double          R   = 0.5 * std::min(box.domain.xmax - box.domain.xmin,
                                               box.domain.ymax - box.domain.ymin);
    VoronoiSpecimen       out;
    for (std::size_t i = 0; i < box.x.size(); ++i)
      if (std::hypot(box.x[i] - cx, box.y[i] - cy) < R)
        {
          out.x.push_back(box.x[i]);
          out.y.push_back(box.y[i]);
          out.radius.push_back(box.radius[i]);
        }
    out.domain       = ClipDomain::circle(cx, cy, R, sides);
    out.tessellation = laguerre_tessellation(out.x, out.y, out.radius, out.domain);
    return out;
  }

  void VoronoiLabParams::validate(const std::string &where) const
  {
    const double inf = HUGE_VAL;
    check_range(where, "confining_pressure", confining_pressure, 0, inf, false, true);
    check_range(where, "strain_rate", strain_rate, 0, inf, true, true);
    check_range(where, "load_fraction", load_fraction, 0, 1, false, true);
    check_range(where, "strain_limit", strain_limit, 0, inf, true, true);
    check_range(where, "step_limit", double(step_limit), 0, inf, true, true);
    check_range(where, "safety", safety, 0, 1, true, false);
    check_range(where, "damping", damping, 0, 1, false, true);
    check_range(where, "platen_friction", platen_friction, 0, inf, false, true);
    check_range(where, "history_strain", history_strain, 0, inf, true, true);
    check_range(where, "fit_lo", fit_lo, 0, 1, false, true);
    check_range(where, "fit_hi", fit_hi, fit_lo, 1, true, false);
    check_range(where, "ratio_limit", ratio_limit, 0, inf, true, true);
    check_range(where, "disk_platen_cone", disk_platen_cone, 0, 90, true, false);
    flexible_mesh.validate(where);
    if (test != VoronoiTest::confined_compression && confining_pressure != 0)
      throw InputError(where + ": confining_pressure is for the confined test only");
  }

  void count_cracks(const RigidVoronoiContacts &c, int &tensile, int &shear)
  {
    tensile = shear = 0;
    for (PointCrack k : c.crack)
      {
        tensile += k == PointCrack::tensile;
        shear += k == PointCrack::shear;
      }
  }

  namespace
  {
    /// Unbalanced-force ratio: sum of the grains' resultant forces over the
    /// sum of the contact point forces (fistPkg §4.2.1's ratio, mean form).
    double unbalanced_ratio(const RigidVoronoiModel &m)
    {
      double unbalanced = 0, contact = 0;
      for (int i = 0; i < m.n_grains(); ++i)
        if (!m.held[i])
          unbalanced += std::hypot(m.fx[i], m.fy[i]);
      const auto &c = m.contacts;
      for (int p = 0; p < c.n_points(); ++p)
        contact += std::hypot(c.fn[p], c.fs[p]);
      return contact > 0 ? unbalanced / contact : 0.0;
    }
    double unbalanced_ratio(const FlexibleVoronoiModel &m)
    {
      double unbalanced = 0, contact = 0;
      for (int i = 0; i < m.mesh.n_nodes(); ++i)
        unbalanced += std::hypot(m.fx[i], m.fy[i]);
      const auto &c = m.contacts;
      for (int p = 0; p < c.n_points(); ++p)
        contact += std::hypot(c.fn[p], c.fs[p]);
      return contact > 0 ? unbalanced / contact : 0.0;
    }

    /// The test on a built model (rigid or flexible: the same boundary
    /// interface, dem/voronoi/boundary.h).
    template <class Model>
    VoronoiLabResult run_test(Model &model, const VoronoiSpecimen &spec,
                              const ContactMaterial &contact, const VoronoiLabParams &p,
                              double wave_speed)
    {
      model.damping     = p.damping;
      const bool   disk = spec.domain.shape == ClipDomain::Shape::circle;
      const double W =
          disk ? 2 * spec.domain.radius : spec.domain.xmax - spec.domain.xmin;
      const double H =
          disk ? 2 * spec.domain.radius : spec.domain.ymax - spec.domain.ymin;
      const double t       = contact.thickness;
      const bool   tension = p.test == VoronoiTest::direct_tension;
      const double Pc =
          p.test == VoronoiTest::confined_compression ? p.confining_pressure : 0;
      // Direct tension: glued grips (bonded platens, no strength); compression:
      // frictional platens (docs/voronoi.md, "Boundary conditions").
      // Brazilian: flat platens tangent to the disk (gap-based).
      const bool      brazilian = p.test == VoronoiTest::brazilian;
      const PlatenLaw law       = tension ? PlatenLaw::glued : PlatenLaw::frictional;
      int             bottom = -1, top = -1;
      if (brazilian)
        {
          bottom =
              model.add_disk_platen(Side::bottom, p.platen_friction, p.disk_platen_cone);
          top = model.add_disk_platen(Side::top, p.platen_friction, p.disk_platen_cone);
        }
      else
        {
          bottom = model.add_platen(Side::bottom, law, p.platen_friction);
          top    = model.add_platen(Side::top, law, p.platen_friction);
        }

      VoronoiLabResult r;
      r.n_grains =
          model.n_grains() - static_cast<int>(spec.tessellation.empty_cells.size());
      r.n_contacts = model.contacts.n_contacts();
      r.n_points   = model.contacts.n_points();
      // Contacts that form during the test lower the step (stable_time_step.h);
      // loading is by platen velocity, so the physical time carries on.
      StableTimeStep<Model> dt(model, p.safety);
      r.time_step    = dt.value();
      double time    = 0;
      auto   advance = [&]() {
        model.step(dt.value());
        time += dt.value();
        dt.update(model);
      };

      // ---- confinement: Pc on all four sides, to equilibrium ------------------
      if (Pc > 0)
        {
          for (Side s : {Side::bottom, Side::right, Side::top, Side::left})
            model.set_pressure(s, Pc);
          for (; r.confining_steps < p.confining_step_limit; ++r.confining_steps)
            {
              advance();
              if (r.confining_steps % 10 == 9 && unbalanced_ratio(model) < p.ratio_limit)
                break;
            }
        }
      // ---- axial loading ---------------------------------------------------------
      // The top and bottom keep the traction Pc; the platens carry the
      // deviator. Strains from here on.
      model.activate_platen(bottom);
      model.activate_platen(top);
      const double v           = 0.5 * p.strain_rate * H * (tension ? 1 : -1);
      model.platens[top].vy    = v;
      model.platens[bottom].vy = -v;
      const double uy_top0 = model.platens[top].uy, uy_bot0 = model.platens[bottom].uy;
      const double ux_right0 = model.side_displacement(Side::right, 0);
      const double ux_left0  = model.side_displacement(Side::left, 0);
      const double area      = W * t;
      const double R         = 0.5 * H; // Brazilian: disk radius (W = H = 2R)

      auto measure = [&](VoronoiLabRow &row) {
        row.axial_strain =
            ((model.platens[top].uy - uy_top0) - (model.platens[bottom].uy - uy_bot0)) /
            H;
        // Force of the grains on the top platen is +y in compression: the
        // platen stress (tension positive) is minus the mean over the two.
        const double platen_stress =
            -0.5 * (model.platens[top].fy - model.platens[bottom].fy) / area;
        row.axial_stress = platen_stress - Pc;
        row.load         = tension ? platen_stress : -platen_stress;
        if (brazilian)
          {
            // fistPkg Eq. 24 (dem/specimen/lab_tests.h, brazilian_strength):
            // sigma_t = F / (pi R t), F the mean platen force; the axial
            // stress is the mean over the diameter, -F / (2 R t).
            const double F   = 0.5 * (model.platens[top].fy - model.platens[bottom].fy);
            row.axial_stress = -F / (2 * R * t);
            row.load         = brazilian_strength(F, R, t);
          }
      };
      // Gauge length: between the mean centres of the side grains (see
      // RigidVoronoiModel::side_displacement).
      const double gauge =
          model.side_position(Side::right, 0) - model.side_position(Side::left, 0);
      auto lateral = [&]() {
        if (brazilian) // no sides: not measured
          return 0.0;
        return ((model.side_displacement(Side::right, 0) - ux_right0) -
                (model.side_displacement(Side::left, 0) - ux_left0)) /
               gauge;
      };

      double next_row = p.history_strain;
      bool   new_peak = false;
      // The post-peak end of the bonded tests (post_peak_end.h), fed every
      // step and judged over the round trip of a compression wave along
      // the loading axis: a drop after cracking since its peak, so neither
      // start-up noise nor the inertial spike of the platens starting at
      // full speed can end the test; one crack is enough in all (a specimen
      // of tens of grains).
      PostPeakEnd   post_peak_end(p.load_fraction, 1,
                                wave_speed > 0 ? 2 * H / wave_speed : 0);
      std::int64_t &k = r.loading_steps;
      r.ended_by      = "step limit";
      r.status        = VoronoiLabStatus::step_limit_reached;
      for (; k < p.step_limit; ++k)
        {
          const double time_before = time;
          advance();
          VoronoiLabRow row;
          row.step = k + 1;
          row.time = time;
          measure(row);
          // Cracks are counted (an O(contacts) scan) only when a window
          // closes or a row is written, once when both fall on this step.
          bool       post_peak     = false;
          const bool window_closed = post_peak_end.add_step(time - time_before, row.load);
          if (window_closed)
            {
              count_cracks(model.contacts, row.cracks_tensile, row.cracks_shear);
              post_peak = post_peak_end.failed(row.cracks_tensile + row.cracks_shear);
            }
          if (row.load > r.peak_load)
            {
              r.peak_load   = row.load;
              r.peak_stress = brazilian ? row.load : std::abs(row.axial_stress);
              if (brazilian)
                r.peak_force = row.load * M_PI * R * t;
              r.peak_strain = std::abs(row.axial_strain);
              new_peak      = true;
            }
          const bool at_limit = std::abs(row.axial_strain) >= p.strain_limit;
          if (std::abs(row.axial_strain) >= next_row || at_limit || post_peak)
            {
              row.lateral_strain = lateral();
              if (!window_closed)
                count_cracks(model.contacts, row.cracks_tensile, row.cracks_shear);
              if (new_peak)
                {
                  // Crack counts at the peak: those of the first row at or
                  // after the peak step (rows are history_strain apart).
                  r.cracks_tensile_peak = row.cracks_tensile;
                  r.cracks_shear_peak   = row.cracks_shear;
                  new_peak              = false;
                }
              r.history.push_back(row);
              while (next_row <= std::abs(row.axial_strain))
                next_row += p.history_strain;
            }
          if (post_peak || at_limit)
            {
              r.ended_by = post_peak ? "post-peak" : "strain limit";
              r.status   = VoronoiLabStatus::ok;
              ++k;
              break;
            }
        }
      count_cracks(model.contacts, r.cracks_tensile, r.cracks_shear);
      r.final_time_step = dt.value();
      r.new_contacts    = model.contacts.n_contacts() - r.n_contacts;

      // ---- E and nu: rows of the loading branch within the fit window --------
      std::vector<double> ea, load, el;
      for (const auto &row : r.history)
        {
          if (std::abs(row.axial_strain) > r.peak_strain)
            break; // past the peak: the loading branch has ended
          if (row.load >= p.fit_lo * r.peak_load && row.load <= p.fit_hi * r.peak_load)
            {
              ea.push_back(std::abs(row.axial_strain));
              load.push_back(row.load);
              el.push_back(tension ? row.lateral_strain : -row.lateral_strain);
            }
        }
      if (ea.size() >= 2 && !brazilian) // no elastic constants from the disk
        {
          r.E  = ls_slope(ea, load);
          r.nu = -ls_slope(ea, el);
        }
      return r;
    }
  } // namespace

  namespace
  {
    void check_specimen_shape(const VoronoiSpecimen &spec, const VoronoiLabParams &p)
    {
      if ((spec.domain.shape == ClipDomain::Shape::circle) !=
          (p.test == VoronoiTest::brazilian))
        throw InputError("Voronoi lab test: the Brazilian test needs a disk specimen, "
                         "the others a rectangle");
    }
  } // namespace

  VoronoiLabResult run_voronoi_lab_test(const VoronoiSpecimen &spec,
                                        const ContactMaterial &contact, double density,
                                        const VoronoiLabParams           &p,
                                        std::optional<RigidVoronoiModel> *final_model)
  {
    p.validate("Voronoi lab test");
    check_specimen_shape(spec, p);
    RigidVoronoiModel model(spec.tessellation, spec.x, spec.y, spec.radius, density,
                            contact, p.scheme);
    // Compression-wave speed of the cell assembly: the contact springs are
    // its only compliance, E ~ kn d with d the mean disk diameter the cells
    // were built on (E_c itself in deformability mode).
    double d = 0;
    for (double radius : spec.radius)
      d += 2 * radius / spec.radius.size();
    const double E =
        contact.deformability_mode() ? contact.contact_modulus : contact.kn * d;
    VoronoiLabResult r = run_test(model, spec, contact, p, std::sqrt(E / density));
    if (final_model)
      final_model->emplace(std::move(model));
    return r;
  }

  VoronoiLabResult run_flexible_voronoi_lab_test(
      const VoronoiSpecimen &spec, const ContactMaterial &contact,
      const GrainElasticity &grain, const VoronoiLabParams &p,
      std::optional<FlexibleVoronoiModel> *final_model)
  {
    p.validate("Voronoi lab test");
    check_specimen_shape(spec, p);
    if (grain.thickness != contact.thickness)
      throw InputError("Voronoi lab test: the grain and contact thicknesses differ");
    FlexibleVoronoiModel model(spec.tessellation, spec.x, spec.y, spec.radius, grain,
                               contact, p.scheme, p.flexible_mesh);
    // The grains' own wave speed: an upper bound of the assembly's (the
    // contacts add compliance), so the shortest post-peak window.
    VoronoiLabResult r = run_test(model, spec, contact, p,
                                  std::sqrt(grain.youngs_modulus / grain.density));
    if (final_model)
      final_model->emplace(std::move(model));
    return r;
  }

  namespace
  {
    // The benchmark scene: Laguerre cells of a jittered hexagonal lattice,
    // spacing 1 mm, radii 0.4-0.5 mm, about n_grains grains; an intact
    // bonded contact material (every point runs the law).
    struct CostScene
    {
      std::vector<double> x, y, r;
      Tessellation        tess;
      ContactMaterial     cm;
      std::mt19937_64     rng;
    };

    CostScene cost_scene(int n_grains, int steps, std::uint64_t seed, const char *where)
    {
      check_range(where, "n_grains", n_grains, 4, HUGE_VAL);
      check_range(where, "steps", steps, 1, HUGE_VAL);
      CostScene    sc;
      const double h  = 1e-3;
      const int    nx = std::max(2, (int)std::lround(std::sqrt(n_grains / 0.866)));
      const int    ny = std::max(2, (int)std::lround(n_grains / (double)nx));
      sc.rng.seed(seed);
      std::uniform_real_distribution<double> u(-1, 1);
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          {
            sc.x.push_back((i + 0.5 + 0.5 * (j % 2)) * h + 0.1 * h * u(sc.rng));
            sc.y.push_back((j + 0.5) * 0.866 * h + 0.1 * h * u(sc.rng));
            sc.r.push_back(0.45 * h + 0.05 * h * u(sc.rng));
          }
      sc.tess = laguerre_tessellation(
          sc.x, sc.y, sc.r, ClipDomain::rectangle(0, 0, (nx + 0.5) * h, ny * 0.866 * h));
      sc.cm.kn                      = 5e13;
      sc.cm.kratio                  = 1.5;
      sc.cm.tensile_strength        = 1e7;
      sc.cm.cohesion                = 3e7;
      sc.cm.friction                = 0.5;
      sc.cm.tensile_fracture_energy = 10;
      sc.cm.shear_fracture_energy   = 50;
      return sc;
    }

    template <class Model>
    double seconds_per_grain_step(Model &model, int steps, double *time_step)
    {
      const double dt = model.stable_time_step(0.5);
      if (time_step)
        *time_step = dt;
      const auto start = std::chrono::steady_clock::now();
      for (int s = 0; s < steps; ++s)
        model.step(dt);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return seconds / (double(model.n_grains()) * steps);
    }
  } // namespace

  double voronoi_cost_per_grain_step(int n_grains, int steps, std::uint64_t seed,
                                     double *time_step)
  {
    CostScene sc = cost_scene(n_grains, steps, seed, "voronoi_cost_per_grain_step");
    RigidVoronoiModel model(sc.tess, sc.x, sc.y, sc.r, 2650, sc.cm);
    // Small random velocities: the contacts stay elastic, every point runs
    // the law (the cost of an intact bonded material).
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < model.n_grains(); ++i)
      if (!model.held[i])
        {
          model.vx[i]    = 1e-3 * u(sc.rng);
          model.vy[i]    = 1e-3 * u(sc.rng);
          model.omega[i] = 1.0 * u(sc.rng);
        }
    return seconds_per_grain_step(model, steps, time_step);
  }

  double flexible_voronoi_cost_per_grain_step(int n_grains, int steps, std::uint64_t seed,
                                              double *time_step)
  {
    CostScene sc =
        cost_scene(n_grains, steps, seed, "flexible_voronoi_cost_per_grain_step");
    GrainElasticity grain;
    grain.youngs_modulus = 70e9; // a granite's grains
    grain.poisson_ratio  = 0.25;
    grain.density        = 2650;
    grain.thickness      = sc.cm.thickness;
    FlexibleVoronoiModel model(sc.tess, sc.x, sc.y, sc.r, grain, sc.cm);
    // Small random nodal velocities: the elements and contacts stay
    // elastic, every point runs the law.
    std::uniform_real_distribution<double> u(-1, 1);
    for (std::size_t m = 0; m < model.vx.size(); ++m)
      {
        model.vx[m] = 1e-3 * u(sc.rng);
        model.vy[m] = 1e-3 * u(sc.rng);
      }
    return seconds_per_grain_step(model, steps, time_step);
  }
} // namespace demfem::dem::voronoi
