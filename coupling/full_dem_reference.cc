#include "coupling/full_dem_reference.h"

#include "coupling/excavation_measures.h"
#include "dem/io/json_number.h"
#include "dem/io/vtk_output.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace demfem::coupling
{
  using dem::Vec;

  // ---------------------------------------------------------------- servo

  template <int dim>
  MembraneServo<dim>::MembraneServo(const dem::Model<dim> &m, int wall,
                                    const MembraneServoParams &pp, double mean_diameter,
                                    double contact_stiffness_floor)
      : p(pp)
      , d(mean_diameter)
      , k_floor(contact_stiffness_floor)
  {
    dem::check_range("membrane servo", "alpha", p.alpha, 0, 1, true);
    dem::check_range("membrane servo", "tolerance", p.tolerance, 0, 1, true);
    dem::check_range("membrane servo", "max step", p.max_step, 0, 1, true);
    const auto &W = m.walls;
    if constexpr (dim == 2)
      {
        // Ring order: follow the facets of the wall (each vertex starts one).
        std::vector<int> next(W.vertex.size(), -1);
        int              first = -1;
        for (std::size_t f = 0; f < W.n_facets(); ++f)
          if (W.facet_wall[f] == wall)
            {
              next[W.facet[f][0]] = W.facet[f][1];
              if (first < 0)
                first = W.facet[f][0];
            }
        for (int v = first; v >= 0 && (ring.empty() || v != first); v = next[v])
          {
            ring.push_back(v);
            if (ring.size() > W.vertex.size())
              break;
          }
        if (ring.size() < 8 || next[ring.back()] != first)
          throw std::runtime_error("membrane servo: wall " + std::to_string(wall) +
                                   " is not a closed ring of facets");
      }
    else
      {
        // The lateral surface: its facets, and its vertices in id order.
        slot.assign(W.vertex.size(), -1);
        for (std::size_t f = 0; f < W.n_facets(); ++f)
          if (W.facet_wall[f] == wall)
            {
              facets.push_back(int(f));
              for (const int v : W.facet[f])
                slot[v] = 0;
            }
        for (std::size_t v = 0; v < slot.size(); ++v)
          if (slot[v] == 0)
            {
              slot[v] = int(ring.size());
              ring.push_back(int(v));
            }
        if (facets.size() < 8)
          throw std::runtime_error("membrane servo: wall " + std::to_string(wall) +
                                   " has fewer than 8 facets");
        // Columns: the vertices above one another (same xy), which move
        // together so that the membrane stays a prism (plane strain).
        std::map<std::pair<long, long>, std::vector<int>> by_xy;
        const double                                      q = 1e-6 * d;
        for (std::size_t j = 0; j < ring.size(); ++j)
          by_xy[{std::lround(W.vertex[ring[j]][0] / q),
                 std::lround(W.vertex[ring[j]][1] / q)}]
              .push_back(int(j));
        for (auto &[xy, c] : by_xy)
          columns.push_back(c);
      }
  }

  namespace
  {
    // 3D: a facet's area vector n A, oriented away from the axis (the
    // membrane stays star-shaped about it), and its centroid.
    std::pair<Vec<3>, Vec<3>> outward_area(const dem::Walls<3>      &W,
                                           const std::array<int, 3> &f)
    {
      const Vec<3> &x0 = W.vertex[f[0]], &x1 = W.vertex[f[1]], &x2 = W.vertex[f[2]];
      Vec<3>        nA = 0.5 * (x1 - x0).cross(x2 - x0);
      const Vec<3>  c  = (x0 + x1 + x2) / 3;
      if (c.head<2>().dot(nA.head<2>()) < 0)
        nA = -nA;
      return {nA, c};
    }
  } // namespace

  template <int dim>
  std::vector<Vec<dim>> MembraneServo<dim>::target_forces(const dem::Model<dim> &m,
                                                          double                 lf) const
  {
    const std::size_t     n = ring.size();
    std::vector<Vec<dim>> F(n, Vec<dim>::Zero());
    if constexpr (dim == 2)
      {
        // Orientation of the ring: outward normal of edge a->b is (t_y, -t_x)
        // for a counter-clockwise ring, the opposite otherwise.
        const auto  &X    = m.walls.vertex;
        const double sign = enclosed(m) > 0 ? 1.0 : -1.0;
        for (std::size_t e = 0; e < n; ++e)
          {
            const Vec<2> &xa = X[ring[e]], &xb = X[ring[(e + 1) % n]];
            const Vec<2>  t = xb - xa;
            // n_e L_e (outward normal times edge length)
            const Vec<2> nL = sign * Vec<2>(t[1], -t[0]);
            // traction on the body sigma0 n; the grains push the wall with
            // its negative, half to each end of the edge
            const Vec<2> f = -0.5 * lf * (target * nL);
            F[e] += f;
            F[(e + 1) % n] += f;
          }
      }
    else
      for (const int f : facets)
        {
          // a third of the facet's traction force to each of its vertices
          // (the xy traction: the lateral normal has no z component on a
          // straight membrane, and the vertices move in xy only)
          const auto   nA = outward_area(m.walls, m.walls.facet[f]).first;
          const Vec<3> t(-lf / 3 * (target(0, 0) * nA[0] + target(0, 1) * nA[1]),
                         -lf / 3 * (target(1, 0) * nA[0] + target(1, 1) * nA[1]), 0);
          for (const int v : m.walls.facet[f])
            F[slot[v]] += t;
        }
    return F;
  }

  template <int dim>
  double MembraneServo<dim>::enclosed(const dem::Model<dim> &m) const
  {
    const auto &X = m.walls.vertex;
    double      A = 0;
    if constexpr (dim == 2)
      {
        // signed shoelace area (> 0: counter-clockwise)
        for (std::size_t e = 0; e < ring.size(); ++e)
          A += dem::cross2(X[ring[e]], X[ring[(e + 1) % ring.size()]]);
        return 0.5 * A;
      }
    else
      {
        // V = (1/2) sum over the lateral facets of c_xy . (n A)_xy (the
        // divergence of (x, y) is 2; the planes z = 0, t add nothing)
        for (const int f : facets)
          {
            const auto [nA, c] = outward_area(m.walls, m.walls.facet[f]);
            A += c.template head<2>().dot(nA.template head<2>());
          }
        return 0.5 * A;
      }
  }

  template <int dim>
  Eigen::Matrix2d MembraneServo<dim>::held_stress(const dem::Model<dim> &m) const
  {
    Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
    for (const int v : ring)
      s -= m.walls.vertex_force[v].template head<2>() *
           m.walls.vertex[v].template head<2>().transpose();
    s /= std::abs(enclosed(m));
    return 0.5 * (s + s.transpose());
  }

  template <int dim>
  double MembraneServo<dim>::relative_error(const dem::Model<dim> &m, double lf) const
  {
    return (held_stress(m) - lf * target).norm() / target.norm();
  }

  template <int dim>
  void MembraneServo<dim>::update(dem::Model<dim> &m, double lf) const
  {
    auto &W = m.walls;
    // Normal stiffness on each vertex: contacts on its facets, split by the
    // barycentric weights of their contact points (as the forces are).
    std::vector<double> k(W.vertex.size(), 0.0);
    for (int g = 0; g < m.n_groups(); ++g)
      {
        const auto &grp = m.group(g);
        for (std::size_t c = 0; c < grp.size(); ++c)
          if (grp.is_wall[c] && grp.active(c))
            {
              const auto  &f  = W.facet[grp.end2[c]];
              const double kn = grp.stiffness(c, m.particles).kn;
              for (int a = 0; a < dim; ++a)
                k[f[a]] += grp.facet_weights[c][a] * kn;
            }
      }
    const double dt = m.timestep();
    if (!(dt > 0))
      throw std::runtime_error("membrane servo: the model has no fixed time step");
    const auto   F    = target_forces(m, lf);
    const double vmax = p.max_step * d / dt;
    if constexpr (dim == 3)
      {
        // A column's vertices move as one (the membrane stays a prism, the
        // plane-strain boundary): the column's force error over its
        // stiffness (moving vertices one by one, measured, left the
        // membrane uneven along z and broke 40 % more bonds near it).
        for (const auto &c : columns)
          {
            Vec<dim> err = Vec<dim>::Zero();
            double   kc  = 0;
            for (const int j : c)
              {
                err += W.vertex_force[ring[j]] - F[j];
                kc += std::max(k[ring[j]], k_floor);
              }
            err[dim - 1] = 0; // in the xy plane: the slab walls hold z
            Vec<dim> vel = p.alpha * err / (kc * dt);
            if (vel.norm() > vmax)
              vel *= vmax / vel.norm();
            for (const int j : c)
              W.vertex_velocity[ring[j]] = vel;
          }
      }
    else
      for (std::size_t j = 0; j < ring.size(); ++j)
        {
          const int v = ring[j];
          // error > 0 along the outward push: too much force, open the
          // membrane
          const Vec<dim> err = W.vertex_force[v] - F[j];
          Vec<dim>       vel = p.alpha * err / (std::max(k[v], k_floor) * dt);
          if (vel.norm() > vmax)
            vel *= vmax / vel.norm();
          W.vertex_velocity[v] = vel;
        }
  }

  template class MembraneServo<2>;
  template class MembraneServo<3>;

  // ------------------------------------------------------------ parameters

  void FullDemReferenceParams::validate(const std::string &w) const
  {
    const double inf = HUGE_VAL;
    if (dimension != 2 && dimension != 3)
      throw dem::InputError(w + ": Problem/dimension must be 2 or 3 (got " +
                            std::to_string(dimension) + ")");
    region.validate(w, dimension); // 3D: the slab thickness too
    dem::check_range(w, "Tunnel/radius", tunnel_radius, 0, inf, true);
    dem::check_range(w, "reference radius factor", min_radius_factor, 1, inf);
    if (region.radius < min_radius_factor * tunnel_radius * (1 - 1e-12))
      {
        std::ostringstream msg;
        msg << w << ": the full-DEM reference radius (" << region.radius
            << " m) must be at least " << min_radius_factor << " x Tunnel/radius ("
            << min_radius_factor * tunnel_radius << " m: the whole domain to "
            << ">= 8 a)";
        throw dem::InputError(msg.str());
      }
    if (tunnel_radius + 3 * region.d_hi > region.radius)
      throw dem::InputError(w + ": Tunnel/radius must be smaller than the reference "
                                "radius by at least three of the largest grains");
    dem::check_range(w, "reference boundary band [grain diameters]", boundary_band, 0,
                     0.25 * region.radius / region.mean_diameter());
    dem::check_range(w, "Tunnel/excavation stages", stages, 1, 1000);
    dem::check_range(w, "Tunnel/damage link length", damage_link_diameters,
                     DamageZone::min_link_grain_diameters,
                     DamageZone::max_link_grain_diameters);
    dem::check_range(w, "timestep safety", safety, 0, 1, true);
    dem::check_range(w, "equilibrium ratio", ratio_tolerance, 0, 1, true);
    dem::check_range(w, "ramp crossing times", ramp_crossing_times, 0,
                     max_ramp_crossing_times, true);
    dem::check_range(w, "step limit", double(phase_step_limit), 1, 1e12);
    dem::check_range(w, "history interval", double(history_interval), 1, 1e12);
    dem::check_range(w, "servo alpha", servo.alpha, 0, 1, true);
    dem::check_range(w, "servo tolerance", servo.tolerance, 0, 1, true);
    if (dimension == 3 && !crack_initiation.empty())
      dem::check_range(w, "Continuum/poisson ratio (the plane-strain sigma_zz)",
                       poisson_ratio, 0, 0.5, true, true);
    for (const auto &[key, v] : crack_initiation)
      dem::check_range(w, "material file's " + key, v, 0, inf, true);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        if (!std::isfinite(sigma0(i, j)))
          throw dem::InputError(w + ": Tunnel/in situ stress must be finite");
    if (!(sigma0.norm() > 0))
      throw dem::InputError(w + ": Tunnel/in situ stress must not be zero (the "
                                "membrane servo needs a target)");
  }

  // ------------------------------------------------------------------- run

  namespace
  {
    std::string num(double x)
    {
      if (!std::isfinite(x))
        return "null";
      std::ostringstream s;
      s << std::setprecision(10) << x;
      return s.str();
    }

    template <int dim>
    struct Reference
    {
      const FullDemReferenceParams       &p;
      std::ostream                       &out;
      dem::Model<dim>                     m;
      int                                 wall = -1;
      std::unique_ptr<MembraneServo<dim>> servo;
      double                              load_factor = 0;
      std::string                         phase       = "build";
      std::ostringstream                  history; // written whole, atomically
      excavation::Record<dim>             exc;
      bool                                excavated    = false;
      bool                                equilibrated = true;
      std::int64_t                        step0        = 0;
      double       reused_genesis_s = 0; // a reused packing's wall time (genesis_cache.h)
      std::size_t  band_bonds       = 0; // bonds made unbreakable near the membrane
      std::int64_t genesis_steps    = 0; // steps of the genesis packing (its own model)
      std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();

      Reference(const FullDemReferenceParams &pp, std::ostream &o)
          : p(pp)
          , out(o)
      {
      }

      double                  d() const { return p.region.mean_diameter(); }
      static constexpr double ke_decay = 1e-4; // equilibrium: KE below this x peak

      void build()
      {
        // Ring of facets about two mean grain diameters long (the rule of
        // the coupling interface, coupling/wall_facet_model.cc), multiple of 8.
        // 3D: the same around, and layers of facets about as high along
        // the slab (plane strain: the slab walls z = 0, t are added by
        // build_region).
        const double R = p.region.radius;
        const auto   n = std::max<std::size_t>(
            32, 8 * static_cast<std::size_t>(std::ceil(2 * M_PI * R / (2 * d()) / 8)));
        if constexpr (dim == 2)
          {
            wall = m.walls.add_wall("membrane");
            std::vector<int> v(n);
            for (std::size_t k = 0; k < n; ++k)
              {
                const double th = 2 * M_PI * k / n;
                v[k] = m.walls.add_vertex(R * Vec<2>(std::cos(th), std::sin(th)));
              }
            for (std::size_t k = 0; k < n; ++k)
              m.walls.add_facet(wall, {{v[k], v[(k + 1) % n]}});
          }
        else
          {
            const double t      = p.region.slab_thickness;
            const auto   layers = std::max(1u, unsigned(std::lround(t / (2 * d()))));
            wall = add_cylinder_ring(m.walls, R, t, unsigned(n), layers, "membrane");
          }
        const RegionGroups G = build_region<dim>(m, p.region, &out);
        // The membrane's neighbourhood: bonds unbreakable (boundary_band).
        const double r_band = R - p.boundary_band * d();
        for (int g = 0; g < m.n_groups() && p.boundary_band > 0; ++g)
          {
            auto &grp = m.group(g);
            if (grp.bond_type() == dem::BondType::none)
              continue;
            for (std::size_t k = 0; k < grp.size(); ++k)
              if (!grp.is_wall[k] && grp.xc[k].template head<2>().norm() > r_band)
                {
                  grp.make_unbreakable(k);
                  ++band_bonds;
                }
          }
        reused_genesis_s = G.genesis_reused ? G.genesis_wall_time_s : 0.0;
        genesis_steps    = G.genesis_steps;
        step0            = m.step_count();
        // Fixed step as the embedded model (safety x DEM critical).
        m.check_timestep = true;
        m.set_timestep(p.safety * m.critical_timestep());
        m.reset_energy_baseline();
        // Floor of the vertex stiffness: one grain-ring contact of the ring
        // law of build_region (kn = E* A / L: 2 E* in 2D, pi r E* for a
        // sphere of the mean size in 3D).
        const double k_floor =
            dim == 2 ? 2 * p.region.emod : M_PI * 0.5 * d() * p.region.emod;
        servo = std::make_unique<MembraneServo<dim>>(m, wall, p.servo, d(), k_floor);
        servo->set_target(p.sigma0);
        out << "full-DEM reference (" << dim << "D): R = " << R << " m, "
            << m.particles.size() << " grains, " << m.walls.n_facets() << " wall facets ("
            << servo->vertices().size() << " membrane vertices), dt = " << m.timestep()
            << " s; " << band_bonds << " bonds within " << p.boundary_band
            << " grain diameters of the membrane unbreakable" << std::endl;
      }

      void record()
      {
        const Eigen::Matrix2d s = servo->held_stress(m);
        history << m.step_count() - step0 << "," << num(m.time()) << "," << phase << ","
                << num(load_factor) << "," << num(m.unbalanced_ratio()) << ","
                << num(m.kinetic_energy()) << "," << num(m.strain_energy()) << ","
                << m.cracks.size() << "," << excavation::count_cracks(m, 0) << ","
                << excavation::count_cracks(m, 1) << "," << num(s(0, 0)) << ","
                << num(s(1, 1)) << "," << num(s(0, 1)) << ","
                << num(servo->relative_error(m, load_factor)) << ","
                << num(excavated ? excavation::wall_convergence(m, exc.ref,
                                                                p.tunnel_radius, d())
                                 : 0.0)
                << "\n";
      }

      // Cycles until the unbalanced ratio is below its tolerance and the
      // membrane holds the stress within the servo tolerance (both checked
      // every 100 steps, after min_steps), or `limit` steps.
      template <class Load>
      void cycle(std::int64_t min_steps, std::int64_t limit, Load load)
      {
        bool   done    = false;
        double ke_peak = 0, ke_last = -1;
        int    n_still = 0;
        for (std::int64_t n = 1; n <= limit; ++n)
          {
            load(n);
            servo->update(m, load_factor);
            m.step();
            const auto s = m.step_count() - step0;
            if (s % p.history_interval == 0)
              record();
            if (n % 100 == 0)
              {
                const double ur = m.unbalanced_ratio();
                const double ke = m.kinetic_energy();
                ke_peak         = std::max(ke_peak, ke);
                // Grains broken free fly into the opening at constant speed
                // (local damping acts on the unbalanced force only, which is
                // zero for them): their kinetic energy stays, so "decayed"
                // also means "no longer changing" (relative change below
                // 1e-3 of the phase peak over two checks, 200 steps).
                const bool still =
                    ke_last >= 0 && std::abs(ke - ke_last) <= 1e-3 * ke_peak;
                n_still = still ? n_still + 1 : 0;
                ke_last = ke;
                if (!std::isfinite(ur))
                  throw dem::InstabilityError(
                      "non-finite unbalanced force at step " + std::to_string(s) +
                      ": the full-DEM reference diverged (time step too large?)");
                if (n % 2000 == 0)
                  out << "[reference " << phase << "] step " << s << "  ratio = " << ur
                      << "  servo error = " << servo->relative_error(m, load_factor)
                      << "  cracks = " << m.cracks.size() << std::endl;
                // The ratio is a mean over all free grains: in a large
                // domain the few grains moving at the tunnel dilute it, so
                // the kinetic energy must also have decayed from its peak in
                // the phase (as the embedded run requires of the continuum).
                if (n >= min_steps && ur < p.ratio_tolerance &&
                    (ke <= ke_decay * ke_peak || n_still >= 2) &&
                    servo->relative_error(m, load_factor) <= p.servo.tolerance)
                  {
                    done = true;
                    break;
                  }
              }
          }
        if (!done)
          {
            equilibrated = false;
            out << "full-DEM reference: phase '" << phase << "' ended at its step limit ("
                << limit << ") with ratio " << m.unbalanced_ratio() << ", servo error "
                << servo->relative_error(m, load_factor) << std::endl;
          }
      }

      FullDemReferenceResult run()
      {
        FullDemReferenceResult r;
        const std::string      dir = p.output_directory;
        std::filesystem::create_directories(dir);
        build();
        r.packing_steps       = step0;
        r.genesis_steps       = genesis_steps;
        r.timestep            = m.timestep();
        r.n_membrane_vertices = servo->vertices().size();
        history << "step,time,phase,load_factor,unbalanced_ratio,kinetic_energy,"
                   "strain_energy,cracks,cracks_tensile,cracks_shear,held_stress_xx,"
                   "held_stress_yy,held_stress_xy,servo_error,wall_convergence_mean\n";
        try
          {
            // Installed with bond breakage suspended, then the strengths act
            // at sigma0, as in the embedded run (coupling/tunnel_run.cc,
            // docs/tunnel.md "In-situ stress installation").
            phase = "in-situ";
            m.suspend_bond_breakage(true);
            const std::int64_t n_ramp = ramp_steps(
                p.ramp_crossing_times * p.region.crossing_time(), m.timestep());
            cycle(n_ramp, n_ramp + p.phase_step_limit, [&](std::int64_t n) {
              load_factor = std::min(1.0, double(n) / n_ramp);
            });
            phase = "in-situ cracking";
            m.suspend_bond_breakage(false);
            cycle(0, p.phase_step_limit, [](std::int64_t) {});
            r.held_stress_insitu = servo->held_stress(m);
            r.servo_error_insitu = servo->relative_error(m, 1.0);
            r.servo_held_insitu  = r.servo_error_insitu <= p.servo.tolerance;
            if constexpr (dim == 2)
              r.region_stress_insitu =
                  region_stress(m, Vec<2>::Zero(), 0.5 * p.region.radius);
            else
              r.region_stress_insitu =
                  region_stress(m, Vec<3>::Zero(), 0.5 * p.region.radius,
                                p.region.slab_thickness)
                      .template topLeftCorner<2, 2>();
            out << "full-DEM reference: in-situ stress held by the membrane ["
                << r.held_stress_insitu(0, 0) << ", " << r.held_stress_insitu(1, 1)
                << ", " << r.held_stress_insitu(0, 1) << "] Pa (error "
                << r.servo_error_insitu << "), grains in r < R/2: ["
                << r.region_stress_insitu(0, 0) << ", " << r.region_stress_insitu(1, 1)
                << ", " << r.region_stress_insitu(0, 1) << "] Pa" << std::endl;

            // Excavation as the embedded tunnel: the removed grains' forces
            // are applied to the remaining ones and relaxed over the stages.
            exc       = excavation::remove_tunnel_grains(m, p.tunnel_radius);
            excavated = true;
            for (int s = 1; s <= p.stages; ++s)
              {
                phase =
                    "excavation " + std::to_string(s) + "/" + std::to_string(p.stages);
                excavation::apply_removed_forces(m, exc, 1.0 - double(s) / p.stages);
                m.reset_energy_baseline();
                cycle(200, p.phase_step_limit, [](std::int64_t) {});
              }
            phase = "equilibrium";
            cycle(0, p.phase_step_limit, [](std::int64_t) {});
          }
        catch (const dem::InstabilityError &e)
          {
            r.diverged  = true;
            r.diagnosis = e.what();
            out << "full-DEM reference: DIVERGED in phase '" << phase << "': " << e.what()
                << std::endl;
          }
        dem::vtkout::write_text_atomically(dir + "/history.csv", history.str());
        const double a             = p.tunnel_radius;
        r.n_particles              = m.particles.size();
        r.n_contacts               = m.n_contacts();
        r.steps                    = m.step_count() - step0;
        r.cracks_total             = excavation::count_cracks(m, -1);
        r.cracks_tensile           = excavation::count_cracks(m, 0);
        r.cracks_shear             = excavation::count_cracks(m, 1);
        r.cracks_before_excavation = excavated ? exc.cracks_before : m.cracks.size();
        r.cracks_near_boundary = excavation::cracks_beyond(m, p.region.radius - 2 * d());
        r.slab_thickness       = dim == 3 ? p.region.slab_thickness : 0.0;
        r.unbreakable_band_bonds = band_bonds;
        r.evaluation_radius      = 0.5 * p.region.radius;
        if (excavated)
          {
            // The zone within R/2; the percentile of all excavation cracks'
            // distances, wherever they are, on its own (no zone needed).
            // The cracks and their zone are found once for the damage
            // zone and the elastic initiation zones.
            const auto x =
                excavation::crack_positions(m, exc.cracks_before, r.evaluation_radius);
            const double link = p.damage_link_diameters * d();
            const auto   zone = connected_to_wall(x, a, link);
            r.damage = measure_damage_zone(x, a, link, zone, p.damage_link_diameters);
            r.damage_zone_depth     = r.damage.depth;
            r.damage_zone_depth_max = r.damage.depth_max;
            for (const auto &[key, threshold] : p.crack_initiation)
              r.initiation_zones.push_back(
                  measure_initiation_zone(x, zone, p.sigma0, a, key, threshold, d(),
                                          dim == 3 ? p.poisson_ratio : -1.0));
            std::vector<double> all;
            for (const auto &x : excavation::crack_positions(m, exc.cracks_before))
              all.push_back(std::max(0.0, std::hypot(x[0], x[1]) - a));
            r.damage_zone_depth_all =
                nearest_rank_percentile(all, DamageZone::percentile);
            r.cracks_beyond_evaluation =
                r.damage.cracks < all.size() ? all.size() - r.damage.cracks : 0;
            if (r.cracks_beyond_evaluation > 0)
              out << "full-DEM reference: warning: " << r.cracks_beyond_evaluation
                  << " excavation crack(s) beyond the evaluation radius R/2 = "
                  << r.evaluation_radius
                  << " m (boundary-influenced, not in the damage-zone "
                  << "depth; unfiltered depth " << r.damage_zone_depth_all << " m)"
                  << std::endl;
          }
        std::vector<std::array<double, 6>> rows;
        if (excavated)
          r.wall_convergence_mean = excavation::wall_convergence(
              m, exc.ref, a, d(), &r.n_wall_particles, &rows);
        r.servo_error_final = servo->relative_error(m, load_factor);
        r.final_ratio       = m.unbalanced_ratio();
        r.equilibrated      = equilibrated && !r.diverged;
        r.status            = r.diverged             ? RunStatus::diverged
                              : !r.servo_held_insitu ? RunStatus::in_situ_not_reached
                              : !r.equilibrated      ? RunStatus::not_equilibrated
                                                     : RunStatus::ok;
        // the reference's cost on its own, a reused packing included
        r.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() +
            reused_genesis_s;
        if (!r.diverged)
          {
            std::ostringstream w;
            w << "x,y,z,ux,uy,uz\n" << std::setprecision(12);
            for (const auto &q : rows)
              w << q[0] << "," << q[1] << "," << q[2] << "," << q[3] << "," << q[4] << ","
                << q[5] << "\n";
            dem::vtkout::write_text_atomically(dir + "/wall_displacement.csv", w.str());
          }
        {
          // every crack: position at breakage, distance from the wall, mode,
          // step, and whether it formed from the excavation on
          std::ostringstream c;
          // (3D: z after y).
          c << (dim == 2 ? "x,y," : "x,y,z,")
            << "distance_from_wall,mode,step,excavation\n"
            << std::setprecision(8);
          for (std::size_t k = 0; k < m.cracks.size(); ++k)
            {
              const auto &q = m.cracks[k];
              c << q.position[0] << "," << q.position[1] << ",";
              if constexpr (dim == 3)
                c << q.position[2] << ",";
              c << q.position.template head<2>().norm() - a << ","
                << (q.mode == 0 ? "tensile" : "shear") << "," << q.step - step0 << ","
                << (excavated && k >= exc.cracks_before ? "yes" : "no") << "\n";
            }
          dem::vtkout::write_text_atomically(dir + "/cracks.csv", c.str());
        }
        using dem::json_number;
        auto stress = [](const auto &t) {
          return nlohmann::ordered_json::array(
              {json_number(t(0, 0)), json_number(t(1, 1)), json_number(t(0, 1))});
        };
        nlohmann::ordered_json j;
        j["status"]    = status_name(r.status);
        j["model"]     = "full-DEM reference (servo-controlled membrane)";
        j["diagnosis"] = r.diagnosis;
        j["dimension"] = dim;
        if (dim == 3)
          j["slab_thickness_m"] = json_number(p.region.slab_thickness);
        j["reference_radius_m"]       = json_number(p.region.radius);
        j["tunnel_radius_m"]          = json_number(a);
        j["n_particles"]              = r.n_particles;
        j["n_contacts"]               = r.n_contacts;
        j["membrane_vertices"]        = r.n_membrane_vertices;
        j["steps"]                    = r.steps;
        j["packing_steps"]            = r.packing_steps;
        j["genesis_steps"]            = r.genesis_steps;
        j["timestep_s"]               = json_number(r.timestep);
        j["wall_time_s"]              = json_number(r.wall_time_s);
        j["cracks_total"]             = r.cracks_total;
        j["cracks_tensile"]           = r.cracks_tensile;
        j["cracks_shear"]             = r.cracks_shear;
        j["cracks_by_type"]           = excavation::cracks_by_type(m);
        j["cracks_before_excavation"] = r.cracks_before_excavation;
        j["cracks_near_boundary"]     = r.cracks_near_boundary;
        j["boundary_band_grains"]     = json_number(p.boundary_band);
        j["unbreakable_band_bonds"]   = r.unbreakable_band_bonds;
        j["damage_zone_depth"]        = json_number(r.damage_zone_depth);
        j["damage_zone_depth_max"]    = json_number(r.damage_zone_depth_max);
        j["damage_zone_depth_all"]    = json_number(r.damage_zone_depth_all);
        j["damage"]                   = r.damage.to_json();
        j["elastic_initiation_zones"] = to_json(r.initiation_zones);
        j["evaluation_radius_m"]      = json_number(r.evaluation_radius);
        j["cracks_beyond_evaluation"] = r.cracks_beyond_evaluation;
        j["wall_convergence_mean"]    = json_number(r.wall_convergence_mean);
        j["wall_particles"]           = r.n_wall_particles;
        j["servo_tolerance"]          = json_number(p.servo.tolerance);
        j["servo_error_insitu"]       = json_number(r.servo_error_insitu);
        j["servo_held_insitu"]        = r.servo_held_insitu;
        j["servo_error_final"]        = json_number(r.servo_error_final);
        j["held_stress_insitu"]       = stress(r.held_stress_insitu);
        j["region_stress_insitu"]     = stress(r.region_stress_insitu);
        j["final_ratio"]              = json_number(r.final_ratio);
        j["equilibrated"]             = r.equilibrated;
        dem::vtkout::write_text_atomically(dir + "/summary.json", j.dump(2) + "\n");
        out << "full-DEM reference: done in " << r.wall_time_s << " s: " << r.n_particles
            << " grains, " << r.steps << " steps, "
            << r.cracks_total - r.cracks_before_excavation
            << " excavation cracks, damage-zone depth " << r.damage_zone_depth
            << " m, wall convergence " << r.wall_convergence_mean << " m" << std::endl;
        return r;
      }
    };
  } // namespace

  FullDemReferenceResult run_full_dem_reference(const FullDemReferenceParams &p,
                                                std::ostream                 &progress)
  {
    p.validate("full-DEM reference");
    if (p.dimension == 3)
      return Reference<3>(p, progress).run();
    return Reference<2>(p, progress).run();
  }
} // namespace demfem::coupling
