#pragma once
// Property rules: how a material sets each contact's property block once,
// when the contact is installed (docs/architecture.md, "Per-contact
// properties"). One rule per law group of a material, whatever the size and
// strength distributions:
//  - deformability (memo §1.10, Eq. 40): kn = E*/L, ks = kn/kappa*, with
//    L = R1 + R2 (ball-ball) or R1 (ball-wall), for every law; laws whose
//    stiffnesses are forces (linear, and the linear part of contact and
//    parallel bonds) take kn = A E*/L with A the cross section of the
//    equivalent beam of radius min(R1, R2) (2 r in 2D, pi r^2 in 3D);
//  - strengths drawn per contact from the material's distributions
//    (fistPkg §2: mean and standard deviation), a Gaussian truncated at zero
//    by redrawing (Random::truncated_normal): the truncated normal on
//    (min, inf), min = 0 unless the material gives a truncation point, so
//    no strength is zero unless the distribution is the single value 0;
//  - the flat-joint radius-multiplier codes and the bonded / gapped / slit
//    installation (fistPkg §2.6.2), which need all joints of the material and
//    so run once after installation.
// Genesis (dem/specimen/genesis_finalize.cc), the lab tests (which cut specimens made
// by genesis) and the tunnel region (coupling/dem_region.cc) use these.
#include "dem/engine/model.h"
#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/parallel_bond_law.h"
#include "dem/specimen/material.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace demfem::dem
{
  /// The deformability method (memo Eq. 40) of one group.
  struct Deformability
  {
    double emod   = 0; ///< E* [Pa]
    double kratio = 0; ///< kappa* (0: ks = 0, memo Table 5 note 2)

    /// Normal stiffness per unit area [Pa/m] for the contact geometry g.
    template <int dim>
    double kn_stress(const ContactGeometry<dim> &g) const
    {
      return emod / g.length();
    }
    /// Normal stiffness as a force per displacement [N/m]: kn_stress * A.
    template <int dim>
    double kn_force(const ContactGeometry<dim> &g) const
    {
      const double r = g.min_radius();
      return (dim == 2 ? 2 * r : M_PI * r * r) * kn_stress(g);
    }
    double ks(double kn) const { return kratio > 0 ? kn / kratio : 0; }
  };

  /// One stream of strength draws for a group (its own generator, seeded
  /// from the specimen's, so the draws depend only on the installation
  /// order).
  class StrengthDraws
  {
  public:
    explicit StrengthDraws(std::uint64_t seed)
        : rng_(std::make_shared<Random>(seed))
    {
    }
    /// One value of d, a Gaussian truncated at d.min (d.sd = 0: the mean).
    double operator()(const Distribution &d) const { return rng_->truncated_normal(d); }

  private:
    std::shared_ptr<Random> rng_; ///< shared by the copies of a rule
  };

  /// Mean of a normal (mean m, sd s) truncated to (min, inf): m + s phi(a) /
  /// (1 - Phi(a)), a = (min - m)/s (the closed form the draws are tested
  /// against).
  double truncated_normal_mean(const Distribution &d);
  /// Standard deviation of the same truncated normal.
  double truncated_normal_sd(const Distribution &d);

  /// Rule of the linear groups (grain-grain and grain-wall): deformability
  /// and friction.
  template <int dim>
  typename ContactGroup<dim, LinearLaw<dim>>::Rule linear_rule(const Deformability &d,
                                                               double friction);

  /// Group parameters of a flat-jointed material's joints (memo Table 5):
  /// element grid, friction, friction angle, radius multiplier, installed
  /// bonded; the per-contact rest comes from flat_joint_rule.
  template <int dim>
  typename FlatJointLaw<dim>::Params flat_joint_params(const MaterialParams &p);

  /// Rule of a flat-jointed material's joints: deformability (memo Eq. 40)
  /// and tensile strength and cohesion drawn per contact.
  template <int dim>
  typename ContactGroup<dim, FlatJointLaw<dim>>::Rule flat_joint_rule(
      const Deformability &d, const Distribution &ten, const Distribution &coh,
      StrengthDraws draws);

  /// Rule of a parallel-bonded material: the linear part by `linear`
  /// (reference gap min(g, 0): no force at installation), the bond by
  /// `bond` (pb_kn = E*_bar / L), strengths drawn per contact.
  template <int dim>
  typename ContactGroup<dim, ParallelBondLaw<dim>>::Rule parallel_bond_rule(
      const Deformability &linear, double friction, const Deformability &bond,
      const Distribution &ten, const Distribution &coh, StrengthDraws draws);

  /// Rule of a contact-bonded material: the linear part (reference gap =
  /// the gap at installation, so the bonded springs start force-free) and
  /// strengths drawn as stresses on the cross section of the equivalent beam
  /// (2 R_min or pi R_min^2), stored as forces.
  template <int dim>
  typename ContactGroup<dim, ContactBondLaw<dim>>::Rule contact_bond_rule(
      const Deformability &linear, double friction, const Distribution &tens,
      const Distribution &shears, StrengthDraws draws);

  /// Flat joints of a material, where they live in the model.
  struct JointList
  {
    int                        group = -1;
    std::vector<std::size_t>   index; ///< contact index in the group
    std::vector<std::uint32_t> i, j;  ///< grains (i < j)
  };

  /// Radius multipliers of a flat-jointed material (fistPkg §2.6.2): code 0
  /// keeps `rmul`; 1 reduces each overlapping pair of faces of a grain
  /// (non-uniform), 2 one factor for all (uniform), until no two faces of a
  /// grain overlap. Sets fj_rmul per contact and re-installs the joints.
  /// Returns {min, max} of the multipliers.
  template <int dim>
  std::pair<double, double> set_radius_multipliers(Model<dim> &m, const JointList &joints,
                                                   int code, double rmul);

  /// Microstructure of a flat-jointed material (fistPkg §2.6.2, Eq. 1): the
  /// first n_B joints of a spatially random list stay bonded (type 1), the
  /// next n_G are gapped (g_o drawn from `gap`, type 2), the rest slit
  /// (type 3). Sets fj_gap0 and fj_mtype per contact.
  template <int dim>
  void designate_microstructure(Model<dim> &m, const JointList &joints, double phi_B,
                                double phi_G, const Distribution &gap, Random &rng);
} // namespace demfem::dem
