#pragma once
// What the tunnel workflow measures on the coupled model (docs/tunnel.md,
// "Damage measures"): the region's stress before excavation, cracks, wall
// convergence, damage zone and cracks reaching the coupling boundary. The
// numbers come from coupling/excavation_measures.h, shared with the full-DEM
// reference; this unit holds what the workflow keeps between phases (the
// excavation record, the stress before excavation) and serializes it with
// checkpoints (dem/io/state_archive.h).
#include "coupling/coupled_model.h"
#include "coupling/excavation_measures.h"
#include "coupling/initiation_zone.h"
#include "coupling/tunnel_result.h"

#include <array>
#include <cstddef>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace demfem::coupling
{
  template <int dim>
  class TunnelMeasures
  {
  public:
    /// `tunnel_radius` a; the region's parameters give the mean grain
    /// diameter (wall band, interface band) and the region's size; the
    /// damage zone's cracks are linked within `link_diameters` of them.
    TunnelMeasures(const CoupledModel<dim> &model, double tunnel_radius,
                   double link_diameters)
        : m(model)
        , a(tunnel_radius)
        , d_mean(model.region_params().mean_diameter())
        , link_diameters(link_diameters)
    {
    }

    /// The elastic prediction the excavation cracks are compared with
    /// (coupling/initiation_zone.h): the in-situ stress, the material's
    /// crack-initiation stresses by material.json key (none: no comparison)
    /// and, in 3D, the Poisson ratio of the plane-strain sigma_zz (2D: < 0).
    void compare_with_elastic_initiation(
        const Eigen::Matrix2d                             &sigma0,
        const std::vector<std::pair<std::string, double>> &crack_initiation, double nu_zz)
    {
      sigma0_           = sigma0;
      crack_initiation_ = crack_initiation;
      nu_zz_            = nu_zz;
    }

    /// The excavation: the grains of the core are removed (their forces on
    /// the rock kept by id) and the displacement reference is taken.
    void excavate(CoupledModel<dim> &model)
    {
      exc       = excavation::remove_tunnel_grains(model.dem, a);
      excavated = true;
    }
    /// The removed core's forces scaled to `remaining` of their value
    /// (support relaxed stage by stage).
    void relax_core_support(CoupledModel<dim> &model, double remaining) const
    {
      excavation::apply_removed_forces(model.dem, exc, remaining);
      model.dem.reset_energy_baseline();
    }

    /// Love-Weber stress of the centre disk r < b/2 (3D section: of its free
    /// core between the end layers), kept as the stress before excavation.
    void measure_in_situ_stress() { stress_before = centre_stress(); }

    /// The same stress now, in plane (the in-situ servo's measure).
    Eigen::Matrix2d centre_stress_in_plane() const
    {
      return centre_stress().template topLeftCorner<2, 2>();
    }

    /// Cracks of a mode (-1 all, 0 tensile, 1 shear) since the start.
    std::size_t cracks(int mode) const { return excavation::count_cracks(m.dem, mode); }

    /// Mean inward radial displacement of the attached grains within one
    /// mean diameter of the wall since the excavation (0 before).
    double convergence(std::size_t                        *n    = nullptr,
                       std::vector<std::array<double, 6>> *rows = nullptr) const
    {
      return excavated ? excavation::wall_convergence(m.dem, exc.ref, a, d_mean, n, rows)
                       : 0.0;
    }

    /// Radius beyond which excavation cracks mean the region is too small:
    /// two mean grain diameters inside the coupling boundary, where the
    /// continuum cannot crack.
    double interface_band_radius() const
    {
      return m.continuum_inner_radius() - 2 * d_mean;
    }

    /// Excavation cracks (in-situ cracks are not the excavation's) beyond
    /// interface_band_radius: {all of them, those of the damage zone}. The
    /// region is too small (status region_too_small) when the zone, the
    /// cracks connected to the wall, reaches the band: the continuum cannot
    /// crack, so the region cuts the zone. An isolated crack there does not
    /// cut the zone; it is counted and warned about.
    std::array<std::size_t, 2> cracks_near_interface() const
    {
      if (!excavated)
        return {{0, 0}};
      return cracks_beyond(excavation::crack_positions(m.dem, exc.cracks_before), a,
                           link_diameters * d_mean, interface_band_radius());
    }

    /// Damage-zone depth of the excavation cracks so far (0 before).
    double damage_zone_depth() const { return excavated ? damage_zone().depth : 0.0; }

    /// The excavation cracks' damage zone (coupling/damage_zone.h).
    DamageZone damage_zone() const
    {
      return excavation::damage_zone(m.dem, exc.cracks_before, a, d_mean, link_diameters);
    }

    /// wall_displacement.csv: the wall grains' reference position and
    /// displacement (x, y, z, ux, uy, uz; z = 0 in 2D).
    std::string wall_displacement_csv() const
    {
      std::vector<std::array<double, 6>> rows;
      convergence(nullptr, &rows);
      std::ostringstream w;
      w << "x,y,z,ux,uy,uz\n" << std::setprecision(12);
      for (const auto &q : rows)
        w << q[0] << "," << q[1] << "," << q[2] << "," << q[3] << "," << q[4] << ","
          << q[5] << "\n";
      return w.str();
    }

    /// The measured fields of the result.
    void fill(TunnelResult &r) const
    {
      r.region_stress_before     = stress_before.template topLeftCorner<2, 2>();
      r.region_stress_before_zz  = dim == 3 ? stress_before(dim - 1, dim - 1) : 0.0;
      r.cracks_total             = cracks(-1);
      r.cracks_tensile           = cracks(0);
      r.cracks_shear             = cracks(1);
      r.cracks_by_type           = excavation::cracks_by_type(m.dem);
      r.cracks_before_excavation = exc.cracks_before;
      // The zone is found once for both measures (damage_zone() and
      // cracks_near_interface() each find it on their own).
      const auto   x    = excavation::crack_positions(m.dem, exc.cracks_before);
      const double link = link_diameters * d_mean;
      const auto   zone = connected_to_wall(x, a, link);
      const auto   near = excavated ? cracks_beyond(x, zone, interface_band_radius())
                                    : std::array<std::size_t, 2>{{0, 0}};
      r.cracks_near_interface      = near[0];
      r.zone_cracks_near_interface = near[1];
      r.region_too_small           = near[1] > 0;
      r.damage                = measure_damage_zone(x, a, link, zone, link_diameters);
      r.damage_zone_depth     = r.damage.depth;
      r.damage_zone_depth_max = r.damage.depth_max;
      r.initiation_zones.clear();
      if (excavated)
        for (const auto &[key, threshold] : crack_initiation_)
          r.initiation_zones.push_back(measure_initiation_zone(
              x, zone, sigma0_, a, key, threshold, d_mean, nu_zz_));
      std::vector<std::array<double, 6>> rows;
      r.wall_convergence_mean = convergence(&r.n_wall_particles, &rows);
      r.wall_points.clear();
      for (const auto &q : rows)
        r.wall_points.push_back({{q[0], q[1]}});
    }

    /// Checkpoint state (one function for saving and loading).
    void serialize(dem::StateArchive &ar)
    {
      ar.io("run.excavated", excavated);
      ar.io("run.cracks_before_excavation", exc.cracks_before);
      ar.io("run.positions_at_excavation", exc.ref);
      ar.io("run.removed_grain_forces", exc.removed_forces);
      ar.io("run.region_stress_before", stress_before);
    }

  private:
    Eigen::Matrix<double, dim, dim> centre_stress() const
    {
      const double r = 0.5 * m.region_params().radius;
      if constexpr (dim == 2)
        return region_stress(m.dem, dem::Vec<2>::Zero(), r);
      else if (m.section())
        return region_stress(m.dem, dem::Vec<3>::Zero(), r, m.end_overlap(),
                             m.region_params().slab_thickness - m.end_overlap());
      else
        return region_stress(m.dem, dem::Vec<3>::Zero(), r,
                             m.region_params().slab_thickness);
    }

    const CoupledModel<dim>        &m;
    double                          a, d_mean, link_diameters;
    excavation::Record<dim>         exc;
    bool                            excavated = false;
    Eigen::Matrix<double, dim, dim> stress_before =
        Eigen::Matrix<double, dim, dim>::Zero();
    Eigen::Matrix2d                             sigma0_ = Eigen::Matrix2d::Zero();
    std::vector<std::pair<std::string, double>> crack_initiation_;
    double                                      nu_zz_ = -1;
  };
} // namespace demfem::coupling
