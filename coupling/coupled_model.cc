#include "coupling/coupled_model.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/utilities.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/tria.h>
#include <deal.II/numerics/data_out.h>

#include "coupling/slaved_layer_model.h"
#include "coupling/wall_facet_model.h"
#include "fem/mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>

namespace demfem::coupling
{
  using dem::Vec;

  void CouplingParams::validate(const std::string &w) const
  {
    if (variant != "slaved-layer" && variant != "wall-facets")
      throw dem::InputError(w + ": Coupling/variant = '" + variant +
                            "' is unknown (allowed: slaved-layer, wall-facets)");
    if (scheme != "explicit" && scheme != "quasi-static" && scheme != "condensed")
      throw dem::InputError(w + ": Coupling/scheme = '" + scheme +
                            "' is unknown (allowed: explicit, quasi-static, condensed)");
    dem::check_range(w, "Coupling/subcycles", subcycles, 1, 1000);
    dem::check_range(w, "Coupling/timestep safety", safety, 0, 100, true);
    dem::check_range(w, "Coupling/relaxation", relaxation, 0, 2, true, true);
    dem::check_range(w, "Coupling/overlap grains", overlap_grains, 0.5, 10);
  }

  void ContinuumParams::validate(const std::string &w, const int dim,
                                 const double          region_radius,
                                 const CouplingParams &kp) const
  {
    const double inf = HUGE_VAL;
    dem::check_range(w, "Continuum/young modulus", young_modulus, 0, inf, true);
    dem::check_range(w, "Continuum/poisson ratio", poisson_ratio, -1, 0.5, true, true);
    if (!(outer_radius > 2 * region_radius))
      throw dem::InputError(w + ": DEM region/radius (" + std::to_string(region_radius) +
                            " m) must be smaller than half of Continuum/outer radius (" +
                            std::to_string(outer_radius) + " m)");
    dem::check_range(w, "Continuum/axial extension", axial_extension, 0, inf);
    if (mass_scaling > 0)
      dem::check_range(w, "Continuum/mass scaling", mass_scaling, 0, 1e6, true);
    else if (kp.variant != "slaved-layer" || kp.scheme != "explicit")
      // The wall facets' grain contacts are not in the coupled critical
      // step: a lighter continuum then went silently wrong (measured:
      // centre stress -597 MPa for a -10 MPa patch test).
      throw dem::InputError(w +
                            ": Continuum/mass scaling = auto is implemented for "
                            "Coupling/variant = slaved-layer with Coupling/scheme = "
                            "explicit (given: " +
                            kp.variant + ", " + kp.scheme +
                            "); give a number, e.g. 1 (the physical density)");
    if (axial_extension > 0)
      {
        if (dim != 3)
          throw dem::InputError(
              w + ": Continuum/axial extension = " + std::to_string(axial_extension) +
              " m: a tunnel section in a 3D continuum needs Problem/dimension = 3 "
              "(allowed in 2D: 0)");
        if (kp.variant != "slaved-layer" || kp.scheme != "explicit")
          throw dem::InputError(
              w + ": Continuum/axial extension = " + std::to_string(axial_extension) +
              " m (a tunnel section in a 3D continuum) is implemented for "
              "Coupling/variant = slaved-layer with Coupling/scheme = explicit (given: " +
              kp.variant + ", " + kp.scheme + "); use axial extension = 0 (the slab)");
        dem::check_range(w, "Tunnel/radius", tunnel_radius, 0, inf, true);
      }
  }

  template <int dim>
  CoupledModel<dim>::CoupledModel(const RegionParams    &region,
                                  const ContinuumParams &continuum,
                                  const CouplingParams &coupling, MPI_Comm comm)
      : rp(region)
      , cp(continuum)
      , kp(coupling)
      , tria(comm)
  {
    rp.validate("DEM region", dim);
    kp.validate("Coupling");
    cp.validate("Continuum", dim, rp.radius, kp);
    if (dealii::Utilities::MPI::n_mpi_processes(comm) != 1)
      throw dem::InputError(
          "the coupled model runs on one MPI rank (run without mpirun)");
  }

  template <int dim>
  CoupledModel<dim>::~CoupledModel() = default;

  template <int dim>
  bool CoupledModel<dim>::in_continuum(const Vec<dim> &x) const
  {
    const double r = x.template head<2>().norm();
    if (r > inner_radius())
      return true;
    if (!section())
      return false;
    const double z = x[dim - 1], h = end_overlap();
    return r > cp.tunnel_radius && (z < h || z > rp.slab_thickness - h);
  }

  template <int dim>
  double CoupledModel<dim>::continuum_inner_radius() const
  {
    return inner_radius();
  }

  template <int dim>
  void CoupledModel<dim>::build(std::ostream *progress)
  {
    // The slaved layer must leave a free core: the continuum starts at
    // r_in = b - h >= b / 2.
    if (!(inner_radius() >= 0.5 * rp.radius))
      throw dem::InputError(
          "Coupling/overlap grains = " + std::to_string(kp.overlap_grains) +
          " mean grain diameters (" + std::to_string(rp.radius - inner_radius()) +
          " m) is too large for DEM region/radius = " + std::to_string(rp.radius) +
          " m (allowed: overlap <= half the region radius)");
    // Continuum annulus r_in <= r <= R; its inner circle gets id 2.
    fem::GeneratedMeshSettings ms;
    ms.radius       = inner_radius();
    ms.outer_radius = cp.outer_radius;
    unsigned int n  = cp.cells_around;
    if (n == 0) // cells about two mean grain diameters wide, multiple of 8
      n = std::max(32u, 8 * static_cast<unsigned int>(std::ceil(
                                2 * M_PI * ms.radius / (2 * rp.mean_diameter()) / 8)));
    ms.cells_around = n;
    if (dim == 3)
      {
        // The slab 0 <= z <= t, element layers about two mean grain
        // diameters thick; z faces on rollers (plane strain, id 4).
        ms.thickness         = rp.slab_thickness;
        ms.layers            = std::max(1u, static_cast<unsigned int>(std::lround(
                                                rp.slab_thickness / (2 * rp.mean_diameter()))));
        ms.plane_strain_slab = true;
      }
    if constexpr (dim == 3)
      if (section())
        {
          // The section's ends must leave a free core between the end layers
          // (at least one largest grain) and the tunnel inside it.
          const double h = end_overlap(), t = rp.slab_thickness;
          if (!(t >= 2 * h + rp.d_hi))
            throw dem::InputError("DEM region/slab thickness = " + std::to_string(t) +
                                  " m is too thin for a tunnel section: the continuum "
                                  "overlaps both ends by " +
                                  std::to_string(h) +
                                  " m (Coupling/overlap grains), so it must be >= " +
                                  std::to_string(2 * h + rp.d_hi) + " m");
          if (!(cp.tunnel_radius < ms.radius))
            throw dem::InputError("Tunnel/radius = " + std::to_string(cp.tunnel_radius) +
                                  " m must be smaller than the section's free core r < " +
                                  std::to_string(ms.radius) + " m");
          fem::SectionMeshSettings ss;
          ss.tunnel_radius  = cp.tunnel_radius;
          ss.hole_radius    = ms.radius;
          ss.section_length = t;
          ss.end_overlap    = h;
          ss.extension      = cp.axial_extension;
          ss.outer_radius   = cp.outer_radius;
          ss.cells_around   = n;
          ss.element_size   = 2 * rp.mean_diameter();
          fem::generate_section_mesh(tria, ss);
        }
    if (!section())
      {
        fem::generate_tunnel_mesh(tria, ms);
        for (const auto &cell : tria.active_cell_iterators())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() &&
                face->boundary_id() == fem::boundary_id::tunnel_wall)
              face->set_boundary_id(fem::boundary_id::interface);
      }

    fem::ExplicitSettings es;
    es.young_modulus = cp.young_modulus;
    es.poisson_ratio = cp.poisson_ratio;
    es.density       = cp.density;
    es.mass_scaling  = cp.mass_scaling > 0 ? cp.mass_scaling : 1.0;
    es.degree        = 1; // vertices = nodes (straight chords, bilinear shapes)
    if (cp.damping >= 0)
      es.damping = cp.damping;
    else
      {
        // Critical damping of the slowest mode, estimated as a quarter shear
        // wave over the annulus: omega_1 ~ (pi/2) c_s / (R - r_in).
        const double G  = cp.young_modulus / (2 * (1 + cp.poisson_ratio));
        const double cs = std::sqrt(G / (cp.density * es.mass_scaling));
        es.damping      = 2 * 0.5 * M_PI * cs / (cp.outer_radius - ms.radius);
      }
    es.fixed = {{fem::boundary_id::far_field, {true, true, true}}};
    if (dim == 3)
      es.fixed.push_back({fem::boundary_id::roller_z, {false, false, true}});
    fem_ = std::make_unique<fem::ExplicitDynamics<dim>>(tria, es);
    fem_->setup();

    points = build_interface(progress);
    fem_->set_coupling_vertices(points);
    accum.assign(points.size(), Vec<dim>::Zero());
    nodal.assign(points.size(), Vec<dim>::Zero());
    const auto coupled_critical_step = [&] {
      // Coupled limit of the continuum step (Gershgorin, as the continuum's
      // own bound): omega_a^2 <= (sum_b |K_ab| + 2 k_att,a) / M_a, the factor
      // 2 bounding the off-diagonal terms of the attached contacts. Without
      // it a sub-cycled slaved layer (k = 4, grains as stiff as the
      // continuum) went silently unstable during the in-situ ramp and
      // settled into a wrong state (region stress +200 MPa for -10 MPa).
      const double        own = fem_->critical_time_step();
      std::vector<double> katt(points.size(), 0.0);
      add_attached_stiffness(katt);
      const auto mass  = fem_->interface_masses();
      double     extra = 0;
      for (std::size_t k = 0; k < katt.size(); ++k)
        if (mass[k] > 0 && std::isfinite(mass[k]))
          extra = std::max(extra, 2 * katt[k] / mass[k]);
      return 2 / std::sqrt(4 / (own * own) + extra);
    };
    // build_region set dem.touching_gap: the carved rim's contacts count.
    fem_crit = coupled_critical_step();
    if (!(cp.mass_scaling > 0) && kp.scheme == "explicit")
      {
        // Automatic mass scaling: every term of omega^2 is over a mass, so
        // the coupled critical step grows as sqrt(s). The lightest continuum
        // whose window k dt still fits (window fraction f): f sqrt(s)
        // crit(1) / k = DEM critical step; never heavier than the physical
        // one (s <= 1). The damping follows (critical for the slowest mode,
        // a proportional to the shear-wave speed, as above).
        const double dem_critical = dem.critical_timestep();
        const double s            = std::min(1.0, std::pow(kp.subcycles * dem_critical /
                                                               (window_limit_fraction() * fem_crit),
                                                           2));
        es.mass_scaling           = s;
        if (!(cp.damping >= 0))
          es.damping /= std::sqrt(s);
        fem_->set_mass_scaling(es.mass_scaling);
        fem_->set_damping(es.damping);
        fem_crit = coupled_critical_step();
      }
    // The scheme, once (coupling_scheme.h): explicit dynamics or the
    // relaxed static response.
    scheme_ =
        make_coupling_scheme<dim>(kp, *fem_, tria, es, points, fem_crit,
                                  affine_installation(), dem.local_damping, progress);
    dem_crit = dem.critical_timestep();
    dt_ =
        kp.safety * std::min(dem_crit, scheme_->dem_step_limit(window_limit_fraction()));
    // A safety above 1 is allowed so that divergence can be shown to be
    // caught; the DEM's own refusal of a supercritical step would hide it.
    dem.check_timestep = kp.safety <= 1;
    dem.set_timestep(dt_);
    dem.reset_energy_baseline();
    if (progress)
      *progress << "coupling (" << variant() << ", " << kp.scheme << "): " << n
                << " cells around r = " << ms.radius << " m, " << points.size()
                << " coupling nodes, " << n_fem_dofs() << " continuum dofs, dt = " << dt_
                << " s (DEM critical " << dem_crit << " s, continuum critical "
                << fem_crit << " s, continuum damping " << es.damping
                << " 1/s, mass scaling " << es.mass_scaling << ")\n";
  }

  template <int dim>
  void CoupledModel<dim>::set_insitu(const Eigen::Matrix2d &s0)
  {
    // Plane-strain in-situ strain of the continuum: eps = ((1 + nu)/E)
    // (sigma - nu tr(sigma) I) in plane; 3D: e_zz = e_xz = e_yz = 0 (szz =
    // nu (sxx + syy)).
    sigma0         = s0;
    const double E = cp.young_modulus, nu = cp.poisson_ratio;
    eps0.setZero();
    eps0.template topLeftCorner<2, 2>() =
        (1 + nu) / E * (s0 - nu * s0.trace() * Eigen::Matrix2d::Identity());
    if (section())
      {
        // The traction of the rock in the tunnel on the continuum's tunnel
        // wall (plane strain in situ: szz = nu (sxx + syy); the wall's normal
        // is radial, so only the in-plane part acts).
        dealii::Tensor<2, dim> sig;
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j)
            sig[i][j] = s0(i, j);
        sig[dim - 1][dim - 1] = nu * s0.trace();
        fem_->set_boundary_traction_load(fem::boundary_id::tunnel_wall, sig);
      }
    scheme_->set_insitu_strain(insitu_strain());
  }

  template <int dim>
  bool CoupledModel<dim>::follows_affine_path() const
  {
    return scheme_->follows_affine_path();
  }

  template <int dim>
  void CoupledModel<dim>::set_interface_strain(const Eigen::Matrix2d &E)
  {
    if (!follows_affine_path() && !E.isZero())
      throw dem::InputError("the in-situ servo's interface strain needs an interface on "
                            "the affine in-situ path (the slaved layer with the explicit "
                            "scheme, or the condensed scheme); this model is " +
                            checkpoint_tag());
    interface_eps.setZero();
    interface_eps.template topLeftCorner<2, 2>() = 0.5 * (E + E.transpose());
  }

  template <int dim>
  Eigen::Matrix2d CoupledModel<dim>::interface_strain() const
  {
    return interface_eps.template topLeftCorner<2, 2>();
  }

  template <int dim>
  dealii::Tensor<2, dim> CoupledModel<dim>::insitu_strain() const
  {
    dealii::Tensor<2, dim> e;
    for (int i = 0; i < dim; ++i)
      for (int j = 0; j < dim; ++j)
        e[i][j] = eps0(i, j);
    return e;
  }

  template <int dim>
  void CoupledModel<dim>::continuum_step()
  {
    const std::size_t n = points.size();
    auto             &f = window_forces;
    f.resize(n);
    const double inv = n_accum > 0 ? 1.0 / n_accum : 0.0;
    for (std::size_t k = 0; k < n; ++k)
      {
        for (int c = 0; c < dim; ++c)
          f[k][c] = inv * accum[k][c];
      }
    fem_->set_interface_forces(f);
    // Force balance: what the continuum holds must equal the mean of the
    // DEM-side interface force (contact sums).
    const auto     held    = fem_->interface_force_sum();
    const Vec<dim> dem_sum = inv * accum_contacts;
    double         diff    = 0;
    if constexpr (dim == 2)
      diff = std::hypot(held[0] - dem_sum[0], held[1] - dem_sum[1]);
    else
      diff = std::sqrt(dealii::Utilities::fixed_power<2>(held[0] - dem_sum[0]) +
                       dealii::Utilities::fixed_power<2>(held[1] - dem_sum[1]) +
                       dealii::Utilities::fixed_power<2>(held[2] - dem_sum[2]));
    imb_last = accum_abs > 0 ? diff / (inv * accum_abs) : 0.0;
    imb_max  = std::max(imb_max, imb_last);
    // Grains follow the affine installation path only where the
    // continuum does (coupling_scheme.h).
    const double                          dl     = load_factor - applied_factor;
    const Eigen::Matrix<double, dim, dim> dE     = interface_eps - applied_interface_eps;
    const double                          length = kp.subcycles * dt_;
    if (scheme_->follows_affine_path())
      hold_grains_on_affine_path(dl, dE);
    scheme_->advance({f, load_factor, dl, release, length, n_steps, hold}, window_u,
                     window_v);
    applied_factor = load_factor;
    // The DEM side of the interface sits at u + E X (the in-situ servo's
    // interface strain, applied at the window's start) and moves with the
    // increment dE over the window, as the free grains do.
    if (!interface_eps.isZero() || !applied_interface_eps.isZero())
      for (std::size_t k = 0; k < window_u.size(); ++k)
        {
          Vec<dim> X;
          for (int c = 0; c < dim; ++c)
            X[c] = points[k][c];
          window_u[k] += applied_interface_eps * X;
          window_v[k] += dE * X / length;
        }
    applied_interface_eps = interface_eps;
    move_interface(window_u, window_v);
    for (auto &a : accum)
      a.setZero();
    accum_contacts.setZero();
    accum_abs = 0;
    n_accum   = 0;
  }

  template <int dim>
  void CoupledModel<dim>::hold_grains_on_affine_path(
      const double dl, const Eigen::Matrix<double, dim, dim> &dE)
  {
    // The load-factor increment dl (and the servo's interface-strain
    // increment dE) is applied over this continuum window (k DEM steps);
    // the grains follow the same affine strain rate.
    auto &P           = dem.particles;
    install_rate      = (dl * eps0 + dE) / (kp.subcycles * dt_);
    const bool moving = dl != 0 || !dE.isZero();
    if (moving && installing_grains.empty())
      {
        for (std::size_t i = 0; i < P.size(); ++i)
          if (P.fixity[i] == dem::fix_none)
            {
              installing_grains.push_back(static_cast<double>(i));
              P.fixity[i] = dem::fix_translation;
            }
      }
    if (!moving && !installing_grains.empty())
      {
        // Released at rest: the relaxation from the affine state starts
        // without the installation's (quasi-static) velocities.
        for (double g : installing_grains)
          {
            const auto i = static_cast<std::size_t>(g);
            P.fixity[i]  = dem::fix_none;
            P.v[i].setZero();
          }
        installing_grains.clear();
      }
  }

  template <int dim>
  void CoupledModel<dim>::step()
  {
    using clock   = std::chrono::steady_clock;
    const auto t0 = clock::now();
    if (n_steps % kp.subcycles == 0)
      continuum_step();
    const auto t1 = clock::now();
    for (double g : installing_grains) // on the affine path (in-situ installation)
      {
        const auto i       = static_cast<std::size_t>(g);
        dem.particles.v[i] = install_rate * dem.particles.x[i];
      }
    try
      {
        dem.step();
      }
    catch (const dem::InstabilityError &e)
      {
        const std::string hint = scheme_->instability_hint();
        if (hint.empty())
          throw;
        throw dem::InstabilityError(e.what() + hint);
      }
    const auto t2 = clock::now();
    ++n_steps;
    for (auto &x : nodal)
      x.setZero();
    last_force = gather_forces(nodal);
    for (std::size_t k = 0; k < nodal.size(); ++k)
      {
        accum[k] += nodal[k];
        accum_abs += nodal[k].norm();
      }
    accum_contacts += last_force;
    ++n_accum;
    const auto seconds = [](clock::duration d) {
      return std::chrono::duration<double>(d).count();
    };
    times.continuum += seconds(t1 - t0);
    times.dem += seconds(t2 - t1);
    times.interface += seconds(clock::now() - t2);
  }

  template <int dim>
  void CoupledModel<dim>::serialize(dem::StateArchive &ar)
  {
    std::vector<double> continuum;
    if (!ar.loading())
      continuum = fem_->save_state();
    ar.io("continuum.state", continuum); // its own layout, checked by load_state
    if (ar.loading())
      fem_->load_state(continuum);
    ar.io("coupling.window_nodal_forces", accum, accum.size());
    ar.io("coupling.window_contact_force", accum_contacts);
    ar.io("coupling.window_force_abs", accum_abs);
    ar.io("coupling.window_steps", n_accum);
    ar.io("coupling.load_factor", load_factor);
    ar.io("coupling.release", release);
    ar.io("coupling.imbalance_max", imb_max);
    ar.io("coupling.imbalance_last", imb_last);
    ar.io("coupling.steps", n_steps);
    ar.io("coupling.applied_load_factor", applied_factor);
    ar.io("coupling.interface_force", last_force);
    ar.io("coupling.install_rate", install_rate);
    ar.io("coupling.installing_grains", installing_grains);
    ar.io("coupling.continuum_held", hold);
    ar.io("coupling.interface_strain", interface_eps);
    ar.io("coupling.applied_interface_strain", applied_interface_eps);
    scheme_->serialize(ar);
  }

  template <int dim>
  double CoupledModel<dim>::continuum_kinetic_energy() const
  {
    return scheme_->kinetic_energy();
  }

  template <int dim>
  double CoupledModel<dim>::continuum_unbalanced_ratio() const
  {
    return scheme_->unbalanced_ratio();
  }

  template <int dim>
  double CoupledModel<dim>::interface_residual() const
  {
    return scheme_->residual();
  }

  template <int dim>
  std::size_t CoupledModel<dim>::n_fem_dofs() const
  {
    return fem_->get_dof_handler().n_dofs();
  }

  template <int dim>
  const std::vector<dealii::Point<dim>> &CoupledModel<dim>::coupling_points() const
  {
    return points;
  }

  template <int dim>
  std::vector<Vec<dim>> CoupledModel<dim>::coupling_displacements() const
  {
    return scheme_->coupling_displacements();
  }

  template <int dim>
  std::string CoupledModel<dim>::continuum_vtu() const
  {
    // Displacement and the total stress per cell (both sides start
    // stress-free, so sigma(u) is the total stress; plane strain, 3D: the
    // slab on rollers), at the cell centre, as a .vtu text.
    dealii::DataOut<dim> data_out;
    data_out.attach_dof_handler(dof_handler());
    std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> ci(
        dim, dealii::DataComponentInterpretation::component_is_part_of_vector);
    const dealii::Vector<double> u = displacement_field();
    data_out.add_data_vector(u, std::vector<std::string>(dim, "displacement"),
                             dealii::DataOut<dim>::type_dof_data, ci);
    const auto  &dh = dof_handler();
    const double E = cp.young_modulus, nu = cp.poisson_ratio;
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    const char  *xyz                       = "xyz";
    std::vector<std::pair<int, int>> comps = {{0, 0}, {1, 1}, {0, 1}};
    if (dim == 3)
      comps.insert(comps.end(), {{2, 2}, {0, 2}, {1, 2}});
    std::vector<dealii::Vector<double>> sig(
        comps.size(), dealii::Vector<double>(dh.get_triangulation().n_active_cells()));
    dealii::MappingQ<dim>  mapping(1);
    dealii::QMidpoint<dim> q;
    dealii::FEValues<dim>  fv(mapping, dh.get_fe(), q, dealii::update_gradients);
    std::vector<std::vector<dealii::Tensor<1, dim>>> g(
        1, std::vector<dealii::Tensor<1, dim>>(dim));
    for (const auto &cell : dh.active_cell_iterators())
      {
        fv.reinit(cell);
        fv.get_function_gradients(u, g);
        double tr = 0;
        for (int a = 0; a < dim; ++a)
          tr += g[0][a][a];
        const auto c = cell->active_cell_index();
        for (std::size_t k = 0; k < comps.size(); ++k)
          {
            const auto [a, b] = comps[k];
            const double e    = 0.5 * (g[0][a][b] + g[0][b][a]);
            sig[k][c]         = (a == b ? lam * tr : 0.0) + 2 * mu * e;
          }
      }
    for (std::size_t k = 0; k < comps.size(); ++k)
      data_out.add_data_vector(
          sig[k], std::string("stress_") + xyz[comps[k].first] + xyz[comps[k].second],
          dealii::DataOut<dim>::type_cell_data);
    data_out.build_patches();
    std::ostringstream text;
    data_out.write_vtu(text);
    return text.str();
  }

  template <int dim>
  dealii::Vector<double> CoupledModel<dim>::displacement_field() const
  {
    return scheme_->displacement_field(load_factor);
  }

  template <int dim>
  const dealii::DoFHandler<dim> &CoupledModel<dim>::dof_handler() const
  {
    return scheme_->dof_handler();
  }

  template <int dim>
  std::unique_ptr<CoupledModel<dim>> make_coupled_model(const RegionParams    &region,
                                                        const ContinuumParams &continuum,
                                                        const CouplingParams  &coupling,
                                                        MPI_Comm               comm)
  {
    coupling.validate("Coupling");
    if (coupling.variant == "wall-facets")
      return std::make_unique<WallFacetModel<dim>>(region, continuum, coupling, comm);
    return std::make_unique<SlavedLayerModel<dim>>(region, continuum, coupling, comm);
  }

  template class CoupledModel<2>;
  template class CoupledModel<3>;
  template std::unique_ptr<CoupledModel<2>> make_coupled_model<2>(const RegionParams &,
                                                                  const ContinuumParams &,
                                                                  const CouplingParams &,
                                                                  MPI_Comm);
  template std::unique_ptr<CoupledModel<3>> make_coupled_model<3>(const RegionParams &,
                                                                  const ContinuumParams &,
                                                                  const CouplingParams &,
                                                                  MPI_Comm);
} // namespace demfem::coupling
