#pragma once
// Smooth-jointed interface in a bonded material (fistPkg §2.8): the contacts
// between grains on opposite sides of a planar joint get the smooth-joint
// law aligned with the joint; new contacts across it get it too.
#include "dem/engine/model.h"
#include "dem/laws/smooth_joint_law.h"

namespace demfem::dem
{
  /// Joint plane through `point` with the orientation (dip, dip direction)
  /// of the smooth-joint parameters `sj` (seed 001 Eq. 1).
  template <int dim>
  struct JointPlane
  {
    Vec<dim>                                point = Vec<dim>::Zero();
    typename SmoothJointLaw<dim>::Params    sj;

    /// Signed distance of x from the plane (positive on the n_j side).
    double side(const Vec<dim> &x) const
    {
      return (x - point).dot(SmoothJointLaw<dim>::joint_normal(sj));
    }
    /// True when the centres of i and j lie on opposite sides (or one on it).
    bool crosses(const Vec<dim> &a, const Vec<dim> &b) const
    {
      return side(a) * side(b) <= 0;
    }
  };

  /// Replaces the law of every existing ball-ball contact across the plane
  /// by the smooth-joint law (a new group with `plane.sj`) and installs the
  /// rule that gives it to new contacts across the plane. Returns the number
  /// of contacts replaced and sets `group` to the smooth-joint group id.
  template <int dim>
  std::size_t insert_smooth_joint(Model<dim> &model, const JointPlane<dim> &plane,
                                  int &group, const std::string &where = "joint");
} // namespace demfem::dem
