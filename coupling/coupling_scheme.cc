#include "coupling/coupling_scheme.h"

#include "coupling/coupled_model.h"

#include <cmath>
#include <sstream>

namespace demfem::coupling
{
  using dem::Vec;

  namespace
  {
    /// What a diverged quasi-static coupling should try next: 0.3 (the
    /// default) from above it, else half the relaxation it had.
    double smaller_relaxation(double relaxation)
    {
      return relaxation > 0.3 ? 0.3 : 0.5 * relaxation;
    }
    /// 200 subcycles (converged where 1 diverged, docs/study.md) from
    /// below, else twice as many.
    unsigned int more_subcycles(unsigned int subcycles)
    {
      return subcycles < 200 ? 200 : 2 * subcycles;
    }

    /// Explicit-explicit staggering (coupled_model.h): the continuum steps
    /// by the window k dt under the window's mean coupling forces; the
    /// interface then moves with the new nodal velocities over the next
    /// window, which interpolates the nodal motion u_n -> u_{n+k} linearly.
    template <int dim>
    class ExplicitScheme : public CouplingScheme<dim>
    {
    public:
      using Window = typename CouplingScheme<dim>::Window;

      ExplicitScheme(const CouplingParams &kp, fem::ExplicitDynamics<dim> &fem,
                     double continuum_critical, bool affine_installation)
          : kp(kp)
          , fem(fem)
          , critical(continuum_critical)
          , affine(affine_installation)
      {
      }

      std::string name() const override { return "explicit"; }

      double dem_step_limit(double window_fraction) const override
      {
        return window_fraction * critical / kp.subcycles;
      }

      void set_insitu_strain(const dealii::Tensor<2, dim> &e) override { eps0 = e; }

      bool follows_affine_path() const override { return affine; }

      void advance(const Window &w, std::vector<Vec<dim>> &u,
                   std::vector<Vec<dim>> &v) override
      {
        // In-situ installation u = lambda eps0 x: the load-factor increment
        // is applied over this continuum step.
        const double dl = w.load_increment;
        if (dl != 0 || far_moving)
          {
            // The whole continuum follows the homogeneous in-situ strain
            // (affine velocity on every node, the far field included; the
            // dynamic part stays the response to the grains): a far-field
            // displacement alone would reach the region only after a wave
            // crossed R and load it dynamically (measured with a far-field
            // ramp of 2000 steps: 12 cracks at safety 0.8, 328 at 0.4; a 3D
            // section's end layers pushed outwards first, 950 tensile
            // cracks).
            const dealii::Tensor<2, dim> L = (dl / w.length) * eps0;
            if (affine)
              fem.set_affine_velocity(L);
            else // the far field alone (wall_facet_model.h)
              fem.set_fixed_velocity([L](const dealii::Point<dim> &x) { return L * x; });
            far_moving = dl != 0;
          }
        fem.set_boundary_load_factor(w.load_factor * w.release);
        // While installing, the continuum follows the affine path exactly
        // (no dynamic part): with its own dynamics the interface lagged the
        // grains held on the path, and sub-cycled windows (k = 2, 4) cracked
        // the region next to the slaved layer during the ramp (167 and 77
        // cracks, measured).
        // Held (in-situ servo): at rest on the path, kinematic.
        fem.set_kinematic(affine && (dl != 0 || w.hold));
        fem.step(w.length);

        // Divergence of the continuum: non-finite or exponentially growing
        // kinetic energy (same criterion as the DEM engine).
        const double ke = fem.kinetic_energy();
        if (growth.update(ke)) // common/growth_monitor.h
          {
            std::ostringstream msg;
            msg << "the continuum diverged at step " << w.step << " (kinetic energy "
                << ke << " J, growing for " << growth.streak << " steps): continuum step "
                << w.length << " s vs its critical step " << critical
                << " s; likely cause: Coupling/timestep safety (" << kp.safety
                << ") or Coupling/subcycles too large, or a stiffness contrast between "
                   "the grains and the continuum";
            throw dem::InstabilityError(msg.str());
          }
        u              = coupling_displacements();
        const auto vel = fem.interface_velocities();
        v.resize(vel.size());
        for (std::size_t k = 0; k < vel.size(); ++k)
          for (int c = 0; c < dim; ++c)
            v[k][c] = vel[k][c];
      }

      double kinetic_energy() const override { return fem.kinetic_energy(); }
      double unbalanced_ratio() const override { return fem.unbalanced_force_ratio(); }
      double residual() const override { return 0; }
      std::string instability_hint() const override { return ""; }

      std::vector<Vec<dim>> coupling_displacements() const override
      {
        const auto            d = fem.interface_displacements();
        std::vector<Vec<dim>> r(d.size());
        for (std::size_t k = 0; k < d.size(); ++k)
          for (int c = 0; c < dim; ++c)
            r[k][c] = d[k][c];
        return r;
      }

      dealii::Vector<double> displacement_field(double) const override
      {
        return dealii::Vector<double>(fem.displacement());
      }

      const dealii::DoFHandler<dim> &dof_handler() const override
      {
        return fem.get_dof_handler();
      }

      void serialize(dem::StateArchive &ar) override
      {
        ar.io("coupling.continuum_kinetic_energy_last", growth.last);
        ar.io("coupling.continuum_growth_steps", growth.streak);
        ar.io("coupling.far_field_moving", far_moving);
      }

    private:
      const CouplingParams       &kp;
      fem::ExplicitDynamics<dim> &fem;
      double                      critical;
      bool                        affine;
      dealii::Tensor<2, dim>      eps0;
      bool                        far_moving = false;
      /// Divergence of the continuum (common/growth_monitor.h).
      instability::GrowthMonitor growth{instability::continuum_kinetic_energy};
    };

    /// Quasi-static scheme (coupled_model.h): target u* = lambda u_far + F f,
    /// relaxed, u_new = u + omega (u* - u), a Dirichlet-Neumann iteration;
    /// the coupling nodes move linearly to u_new over the next window.
    template <int dim>
    class QuasiStaticScheme : public CouplingScheme<dim>
    {
    public:
      using Window = typename CouplingScheme<dim>::Window;

      QuasiStaticScheme(const CouplingParams &kp, const fem::ExplicitDynamics<dim> &fem,
                        const dealii::parallel::distributed::Triangulation<dim> &tria,
                        const fem::ExplicitSettings                             &es,
                        const std::vector<dealii::Point<dim>>                   &points,
                        std::ostream                                            *progress)
          : kp(kp)
          , fem(fem)
          , n(points.size())
      {
        // Static response on the same mesh, far field and coupling nodes;
        // the flexibility is computed once (dim n solves of the factorized
        // K).
        static_ = std::make_unique<fem::StaticInterfaceResponse<dim>>(
            tria, fem::StaticSettings::from(es), points);
        static_->setup();
        flex = static_->flexibility();
        u_far.assign(dim * n, 0.0);
        u_reached.assign(dim * n, 0.0);
        if (progress)
          *progress << "quasi-static continuum: interface flexibility " << flex.m()
                    << " x " << flex.n() << " in "
                    << static_->cost().setup_seconds() +
                           static_->cost().flexibility_seconds
                    << " s, relaxation " << kp.relaxation << "\n";
      }

      std::string name() const override { return "quasi-static"; }

      // No inertia: only the DEM limits dt.
      double dem_step_limit(double) const override { return HUGE_VAL; }

      void set_insitu_strain(const dealii::Tensor<2, dim> &e) override
      {
        eps0         = e;
        const auto r = static_->far_field_response(e);
        for (std::size_t k = 0; k < r.size(); ++k)
          for (int c = 0; c < dim; ++c)
            u_far[dim * k + c] = r[k][c];
      }

      // The relaxed interface lags the grains: holding them on the affine
      // path made the slaved layer unstable (measured); they stay free.
      bool follows_affine_path() const override { return false; }

      void advance(const Window &w, std::vector<Vec<dim>> &u,
                   std::vector<Vec<dim>> &v) override
      {
        // Target u* = lambda u_far + F f, relaxed from the displacement the
        // coupling nodes reached (the previous window's u_new).
        std::vector<double> fv(dim * n), target(dim * n);
        for (std::size_t k = 0; k < n; ++k)
          for (int c = 0; c < dim; ++c)
            fv[dim * k + c] = w.forces[k][c];
        double dnorm = 0, tnorm = 0;
        for (std::size_t i = 0; i < dim * n; ++i)
          {
            double t = w.load_factor * u_far[i];
            for (std::size_t j = 0; j < dim * n; ++j)
              t += flex(i, j) * fv[j];
            target[i] = t;
            dnorm += (t - u_reached[i]) * (t - u_reached[i]);
            tnorm += t * t;
          }
        res = tnorm > 0 ? std::sqrt(dnorm / tnorm) : 0.0;
        if (growth.update(res)) // common/growth_monitor.h
          {
            std::ostringstream msg;
            msg << "the quasi-static coupling diverged at step " << w.step
                << ": the interface residual |u* - u| / |u*| = " << res
                << " grew by more than "
                << 100 * (instability::interface_residual.factor - 1)
                << " % per window for " << growth.streak
                << " windows; likely cause: Coupling/relaxation (" << kp.relaxation
                << ") too large for the stiffness contrast between the grains and the "
                   "continuum (try "
                << smaller_relaxation(kp.relaxation) << "), or Coupling/subcycles ("
                << kp.subcycles
                << ") too small for the DEM to respond within a window (try "
                << more_subcycles(kp.subcycles) << ")";
            throw dem::InstabilityError(msg.str());
          }
        u.resize(n);
        v.resize(n);
        for (std::size_t k = 0; k < n; ++k)
          {
            Vec<dim> du;
            for (int c = 0; c < dim; ++c)
              {
                const std::size_t i = dim * k + c;
                u[k][c]             = u_reached[i];
                du[c]               = kp.relaxation * (target[i] - u_reached[i]);
                u_reached[i] += du[c];
              }
            v[k] = du / w.length;
          }
      }

      double kinetic_energy() const override { return 0; }
      double unbalanced_ratio() const override { return 0; }
      double residual() const override { return res; }

      std::string instability_hint() const override
      {
        // The relaxed static interface drives the grains: a diverging
        // iteration shows first as a DEM instability (overlaps growing, the
        // critical step falling below dt).
        std::ostringstream msg;
        msg << " With the quasi-static coupling (interface residual " << res
            << ") the likely cause is Coupling/relaxation (" << kp.relaxation
            << ") too large for the stiffness contrast between the grains and the "
               "continuum (try "
            << smaller_relaxation(kp.relaxation) << ") or Coupling/subcycles ("
            << kp.subcycles << ") too small for the DEM to respond within a window (try "
            << more_subcycles(kp.subcycles) << ").";
        return msg.str();
      }

      std::vector<Vec<dim>> coupling_displacements() const override
      {
        std::vector<Vec<dim>> r(n);
        for (std::size_t k = 0; k < n; ++k)
          for (int c = 0; c < dim; ++c)
            r[k][c] = u_reached[dim * k + c];
        return r;
      }

      dealii::Vector<double> displacement_field(double load_factor) const override
      {
        // The static field under the current load factor and the latest
        // window's mean nodal forces (held in the explicit continuum's force
        // vector); it equals the relaxed interface motion at convergence.
        static_->solve(load_factor, eps0, fem.interface_forces());
        return dealii::Vector<double>(static_->displacement());
      }

      const dealii::DoFHandler<dim> &dof_handler() const override
      {
        return static_->get_dof_handler();
      }

      void serialize(dem::StateArchive &ar) override
      {
        ar.io("coupling.residual", res);
        ar.io("coupling.residual_last", growth.last);
        ar.io("coupling.residual_growth_steps", growth.streak);
        ar.io("coupling.interface_displacement_reached", u_reached, u_reached.size());
      }

    private:
      const CouplingParams                                      &kp;
      const fem::ExplicitDynamics<dim>                          &fem;
      std::size_t                                                n;
      mutable std::unique_ptr<fem::StaticInterfaceResponse<dim>> static_;
      dealii::FullMatrix<double>                                 flex;
      dealii::Tensor<2, dim>                                     eps0;
      std::vector<double>                                        u_far, u_reached;
      double                                                     res = 0;
      /// Divergence of the relaxation (common/growth_monitor.h).
      instability::GrowthMonitor growth{instability::interface_residual};
    };

    /// Condensed scheme (coupled_model.h): the continuum without inertia,
    /// condensed onto its coupling nodes by its static interface stiffness
    /// K_s = F^-1 (the Schur complement of the stiffness on the coupling
    /// dofs), the coupling nodes stepped with the DEM as PFC steps grains to
    /// equilibrium: M a = f - K_s (u - lambda u_far) with local non-viscous
    /// damping, central differences, M the continuum's lumped masses at the
    /// nodes. At rest the nodes satisfy u = lambda u_far + F f, the static
    /// continuum's answer, so the phase length is the grains' relaxation and
    /// not the continuum's slow dynamics.
    template <int dim>
    class CondensedScheme : public CouplingScheme<dim>
    {
    public:
      using Window = typename CouplingScheme<dim>::Window;

      CondensedScheme(const CouplingParams &kp, const fem::ExplicitDynamics<dim> &fem,
                      const dealii::parallel::distributed::Triangulation<dim> &tria,
                      const fem::ExplicitSettings                             &es,
                      const std::vector<dealii::Point<dim>>                   &points,
                      double continuum_critical, double local_damping,
                      std::ostream *progress)
          : kp(kp)
          , fem(fem)
          , x(points)
          , n(points.size())
          , critical(continuum_critical)
          , alpha(local_damping)
      {
        static_ = std::make_unique<fem::StaticInterfaceResponse<dim>>(
            tria, fem::StaticSettings::from(es), points);
        static_->setup();
        const auto &flex = static_->flexibility();
        // K_s on the free components (a constrained component has a zero
        // row and column in F and stays at rest).
        const auto &free = static_->free_components();
        for (unsigned int i = 0; i < dim * n; ++i)
          if (free[i])
            dofs.push_back(i);
        const auto                 nf = static_cast<unsigned int>(dofs.size());
        dealii::FullMatrix<double> k(nf, nf);
        for (unsigned int a = 0; a < nf; ++a)
          for (unsigned int b = 0; b < nf; ++b)
            k(a, b) = flex(dofs[a], dofs[b]);
        k.gauss_jordan(); // F is symmetric positive definite
        // Row-major and contiguous: the product with it is the scheme's
        // per-step cost.
        stiffness.resize(std::size_t(nf) * nf);
        for (unsigned int a = 0; a < nf; ++a)
          for (unsigned int b = 0; b < nf; ++b)
            stiffness[std::size_t(a) * nf + b] = k(a, b);
        const auto masses = fem.interface_masses();
        mass.resize(nf);
        for (unsigned int a = 0; a < nf; ++a)
          {
            mass[a] = masses[dofs[a] / dim];
            if (!(mass[a] > 0) || !std::isfinite(mass[a]))
              throw dem::InputError("Coupling/scheme = condensed: coupling node " +
                                    std::to_string(dofs[a] / dim) +
                                    " has no finite continuum mass");
          }
        u.assign(nf, 0.0);
        v.assign(nf, 0.0);
        u_far.assign(nf, 0.0);
        f.assign(nf, 0.0);
        elastic.assign(nf, 0.0);
        relative.assign(nf, 0.0);
        if (progress)
          *progress << "condensed continuum: interface stiffness " << nf << " x " << nf
                    << " in "
                    << static_->cost().setup_seconds() +
                           static_->cost().flexibility_seconds
                    << " s, local damping " << alpha << "\n";
      }

      std::string name() const override { return "condensed"; }

      // The nodes' own bound: the condensed stiffness is the Schur
      // complement of the continuum's, so with the same nodal masses its
      // largest frequency is below the coupled continuum's (interlacing),
      // whose Gershgorin bound `critical` counts the attached grains too.
      double dem_step_limit(double window_fraction) const override
      {
        return window_fraction * critical / kp.subcycles;
      }

      void set_insitu_strain(const dealii::Tensor<2, dim> &e) override
      {
        eps0         = e;
        const auto r = static_->far_field_response(e);
        for (std::size_t a = 0; a < dofs.size(); ++a)
          u_far[a] = r[dofs[a] / dim][dofs[a] % dim];
      }

      // The nodes follow lambda eps0 x exactly while lambda rises, as the
      // grains do: both sides are then at the homogeneous state, which the
      // static continuum holds with the interface forces of sigma0.
      bool follows_affine_path() const override { return true; }

      void advance(const Window &w, std::vector<Vec<dim>> &u_start,
                   std::vector<Vec<dim>> &v_window) override
      {
        const std::size_t nf = dofs.size();
        for (std::size_t a = 0; a < nf; ++a)
          f[a] = w.forces[dofs[a] / dim][dofs[a] % dim];
        u_start.assign(n, Vec<dim>::Zero());
        v_window.assign(n, Vec<dim>::Zero());
        for (std::size_t a = 0; a < nf; ++a)
          u_start[dofs[a] / dim][dofs[a] % dim] = u[a];
        if (w.load_increment != 0 || w.hold)
          {
            // Installation: u = lambda eps0 x over the window (held by the
            // in-situ servo: at rest there).
            installing = true;
            for (std::size_t a = 0; a < nf; ++a)
              {
                const unsigned int k = dofs[a] / dim, c = dofs[a] % dim;
                double             ex = 0;
                for (int j = 0; j < dim; ++j)
                  ex += eps0[c][j] * x[k][j];
                v[a]           = w.load_increment / w.length * ex;
                u[a]           = w.load_factor * ex;
                v_window[k][c] = v[a];
              }
            update_residual(w.load_factor);
            return;
          }
        if (installing) // released at rest, as the grains
          {
            installing = false;
            std::fill(v.begin(), v.end(), 0.0);
          }
        update_residual(w.load_factor);
        if (!std::isfinite(res))
          throw dem::InstabilityError(
              "the condensed coupling diverged at step " + std::to_string(w.step) +
              ": non-finite interface force; likely cause: Coupling/timestep safety (" +
              std::to_string(kp.safety) + ") too large");
        // Central differences with PFC local damping (F_d = -alpha |F|
        // sign(v), per component): the nodes' motion is an iteration to
        // the static answer, not the continuum's dynamics.
        for (std::size_t a = 0; a < nf; ++a)
          {
            const double F  = f[a] - elastic[a];
            const double sv = v[a] > 0 ? 1.0 : (v[a] < 0 ? -1.0 : 0.0);
            v[a] += w.length * (F - alpha * std::abs(F) * sv) / mass[a];
            u[a] += w.length * v[a];
            v_window[dofs[a] / dim][dofs[a] % dim] = v[a];
          }
      }

      double kinetic_energy() const override { return 0; }
      double unbalanced_ratio() const override { return 0; }
      double residual() const override { return res; }

      std::string instability_hint() const override
      {
        std::ostringstream msg;
        msg << " With the condensed coupling (interface force residual " << res
            << ") the likely cause is Coupling/timestep safety (" << kp.safety
            << ") too large for the stiffness of the condensed continuum.";
        return msg.str();
      }

      std::vector<Vec<dim>> coupling_displacements() const override
      {
        std::vector<Vec<dim>> r(n, Vec<dim>::Zero());
        for (std::size_t a = 0; a < dofs.size(); ++a)
          r[dofs[a] / dim][dofs[a] % dim] = u[a];
        return r;
      }

      dealii::Vector<double> displacement_field(double load_factor) const override
      {
        // The static field whose coupling nodes are where they are: the
        // nodal forces K_s (u - lambda u_far) reproduce u exactly.
        std::vector<double> held_dofs(dofs.size());
        elastic_force(load_factor, held_dofs);
        std::vector<dealii::Tensor<1, dim>> held(n);
        for (std::size_t a = 0; a < dofs.size(); ++a)
          held[dofs[a] / dim][dofs[a] % dim] = held_dofs[a];
        static_->solve(load_factor, eps0, held);
        return dealii::Vector<double>(static_->displacement());
      }

      const dealii::DoFHandler<dim> &dof_handler() const override
      {
        return static_->get_dof_handler();
      }

      void serialize(dem::StateArchive &ar) override
      {
        ar.io("coupling.residual", res);
        ar.io("coupling.installing", installing);
        ar.io("coupling.condensed_displacement", u, u.size());
        ar.io("coupling.condensed_velocity", v, v.size());
      }

    private:
      /// elastic = K_s (u - lambda u_far), the force the static continuum
      /// needs at its nodes to sit at u; res = |f - elastic| / |elastic|,
      /// the interface's counterpart of the DEM's unbalanced-force ratio.
      void update_residual(double load_factor)
      {
        elastic_force(load_factor, elastic);
        double rn = 0, en = 0;
        for (std::size_t a = 0; a < dofs.size(); ++a)
          {
            rn += (f[a] - elastic[a]) * (f[a] - elastic[a]);
            en += elastic[a] * elastic[a];
          }
        res = en > 0 ? std::sqrt(rn / en) : (rn > 0 ? HUGE_VAL : 0.0);
      }

      /// Below this many rows a parallel region costs more than the product.
      static constexpr std::ptrdiff_t min_threaded_rows = 128;

      /// out = K_s (u - lambda u_far).
      void elastic_force(double load_factor, std::vector<double> &out) const
      {
        const std::size_t nf = dofs.size();
        for (std::size_t b = 0; b < nf; ++b)
          relative[b] = u[b] - load_factor * u_far[b];
        // The dense product is the scheme's per-step cost (608 x 608 in the
        // default example; it grows with the square of the coupling nodes).
        // Each row's sum is taken by one thread in the same order, so the
        // forces do not depend on the thread count
        // (tests/coupling/quasi_static_test.cc).
        const auto rows = static_cast<std::ptrdiff_t>(nf);
#pragma omp parallel for schedule(static) if (rows >= min_threaded_rows)
        for (std::ptrdiff_t a = 0; a < rows; ++a)
          {
            const double *row = stiffness.data() + a * nf;
            double        t   = 0;
            for (std::size_t b = 0; b < nf; ++b)
              t += row[b] * relative[b];
            out[a] = t;
          }
      }

      const CouplingParams                                      &kp;
      const fem::ExplicitDynamics<dim>                          &fem;
      std::vector<dealii::Point<dim>>                            x;
      std::size_t                                                n;
      double                                                     critical, alpha;
      mutable std::unique_ptr<fem::StaticInterfaceResponse<dim>> static_;
      std::vector<unsigned int>                                  dofs;
      std::vector<double>         stiffness; ///< K_s, row-major
      std::vector<double>         mass, u, v, u_far, f, elastic;
      mutable std::vector<double> relative; ///< u - lambda u_far
      dealii::Tensor<2, dim>      eps0;
      double                      res        = 0;
      bool                        installing = false;
    };
  } // namespace

  template <int dim>
  std::unique_ptr<CouplingScheme<dim>> make_coupling_scheme(
      const CouplingParams &kp, fem::ExplicitDynamics<dim> &fem,
      const dealii::parallel::distributed::Triangulation<dim> &tria,
      const fem::ExplicitSettings &es, const std::vector<dealii::Point<dim>> &points,
      double continuum_critical, bool affine_installation, double local_damping,
      std::ostream *progress)
  {
    if (kp.scheme == "quasi-static")
      return std::make_unique<QuasiStaticScheme<dim>>(kp, fem, tria, es, points,
                                                      progress);
    if (kp.scheme == "condensed")
      return std::make_unique<CondensedScheme<dim>>(
          kp, fem, tria, es, points, continuum_critical, local_damping, progress);
    return std::make_unique<ExplicitScheme<dim>>(kp, fem, continuum_critical,
                                                 affine_installation);
  }

#define DEMFEM_INSTANTIATE(D)                                                            \
  template std::unique_ptr<CouplingScheme<D>> make_coupling_scheme<D>(                   \
      const CouplingParams &, fem::ExplicitDynamics<D> &,                                \
      const dealii::parallel::distributed::Triangulation<D> &,                           \
      const fem::ExplicitSettings &, const std::vector<dealii::Point<D>> &, double,      \
      bool, double, std::ostream *);
  DEMFEM_INSTANTIATE(2)
  DEMFEM_INSTANTIATE(3)
#undef DEMFEM_INSTANTIATE
} // namespace demfem::coupling
