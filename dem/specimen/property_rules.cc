#include "dem/specimen/property_rules.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem
{
  double truncated_normal_mean(const Distribution &d)
  {
    if (d.sd <= 0)
      return d.mean;
    const double a   = (d.min - d.mean) / d.sd;
    const double phi = std::exp(-0.5 * a * a) / std::sqrt(2 * M_PI);
    const double Q   = 0.5 * std::erfc(a / std::sqrt(2.0)); // 1 - Phi(a)
    return d.mean + d.sd * phi / Q;
  }

  double truncated_normal_sd(const Distribution &d)
  {
    if (d.sd <= 0)
      return 0;
    const double a      = (d.min - d.mean) / d.sd;
    const double phi    = std::exp(-0.5 * a * a) / std::sqrt(2 * M_PI);
    const double Q      = 0.5 * std::erfc(a / std::sqrt(2.0));
    const double lambda = phi / Q;
    return d.sd * std::sqrt(1 + a * lambda - lambda * lambda);
  }

  template <int dim>
  typename ContactGroup<dim, LinearLaw<dim>>::Rule linear_rule(const Deformability &d,
                                                               double friction)
  {
    return
        [d, friction](const ContactGeometry<dim> &g, typename LinearLaw<dim>::Props &q) {
          q.kn       = d.kn_force(g);
          q.ks       = d.ks(q.kn);
          q.friction = friction;
        };
  }

  template <int dim>
  typename FlatJointLaw<dim>::Params flat_joint_params(const MaterialParams &p)
  {
    typename FlatJointLaw<dim>::Params q;
    q.Nr     = p.fj_Nr;
    q.Nal    = p.fj_Nal;
    q.rmul   = p.fj_rmul;
    q.fric   = p.fric;
    q.fa     = p.fj_fa;
    q.bonded = true;
    return q;
  }

  template <int dim>
  typename ContactGroup<dim, FlatJointLaw<dim>>::Rule flat_joint_rule(
      const Deformability &d, const Distribution &ten, const Distribution &coh,
      StrengthDraws draws)
  {
    return [d, ten, coh, draws](const ContactGeometry<dim>        &g,
                                typename FlatJointLaw<dim>::Props &q) {
      q.kn  = d.kn_stress(g); // memo Eq. 40
      q.ks  = d.ks(q.kn);
      q.ten = draws(ten);
      q.coh = draws(coh);
    };
  }

  template <int dim>
  typename ContactGroup<dim, ParallelBondLaw<dim>>::Rule parallel_bond_rule(
      const Deformability &linear, double friction, const Deformability &bond,
      const Distribution &ten, const Distribution &coh, StrengthDraws draws)
  {
    return [=](const ContactGeometry<dim> &g, typename ParallelBondLaw<dim>::Props &q) {
      q.linear.kn            = linear.kn_force(g);
      q.linear.ks            = linear.ks(q.linear.kn);
      q.linear.friction      = friction;
      q.linear.reference_gap = std::min(g.gap, 0.0);
      q.pb_kn                = bond.kn_stress(g);
      q.pb_ks                = bond.ks(q.pb_kn);
      q.pb_ten               = draws(ten);
      q.pb_coh               = draws(coh);
    };
  }

  template <int dim>
  typename ContactGroup<dim, ContactBondLaw<dim>>::Rule contact_bond_rule(
      const Deformability &linear, double friction, const Distribution &tens,
      const Distribution &shears, StrengthDraws draws)
  {
    return [=](const ContactGeometry<dim> &g, typename ContactBondLaw<dim>::Props &q) {
      q.linear.kn            = linear.kn_force(g);
      q.linear.ks            = linear.ks(q.linear.kn);
      q.linear.friction      = friction;
      q.linear.reference_gap = g.gap; // bonded springs carry kn (g - g_r): no force now
      const double r         = g.min_radius();
      const double A         = dim == 2 ? 2 * r : M_PI * r * r;
      q.cb_tenf              = A * draws(tens); // strengths are stresses (Table 3)
      q.cb_shearf            = A * draws(shears);
    };
  }

  namespace
  {
    template <int dim>
    struct Face
    {
      std::size_t fj;  // index into the joint list
      Vec<dim>    dir; // unit vector from the grain centre towards the face
      double      a;   // distance from the grain centre to the contact plane
      double      m;   // min(R1, R2): face radius = multiplier * m
    };

    /// Half-angle of the cone (3D) or wedge (2D) joining a face to its grain
    /// centre; two faces of one grain overlap iff their half-angles add up to
    /// more than the angle between their directions (fistPkg §2.6.2).
    double half_angle(double R, double a) { return std::atan2(R, a); }
  } // namespace

  template <int dim>
  std::pair<double, double> set_radius_multipliers(Model<dim> &m, const JointList &joints,
                                                   int code, double rmul)
  {
    const std::size_t n = joints.index.size();
    if (n == 0)
      return {rmul, rmul};
    auto               &grp = m.template typed_group<FlatJointLaw<dim>>(joints.group);
    const auto         &P   = m.particles;
    std::vector<double> mult(n, rmul);
    std::vector<std::vector<Face<dim>>> faces(P.size());
    for (std::size_t f = 0; f < n; ++f)
      {
        const auto     geo = grp.geometry(joints.index[f], P, m.walls);
        const auto     i = joints.i[f], j = joints.j[f];
        const double   mr      = std::min(P.radius[i], P.radius[j]);
        const bool     i_first = grp.end1[joints.index[f]] == i;
        const Vec<dim> n_i     = i_first ? geo.n : Vec<dim>(-geo.n);
        faces[i].push_back({f, n_i, (geo.xc - P.x[i]).dot(n_i), mr});
        faces[j].push_back({f, Vec<dim>(-n_i), (P.x[j] - geo.xc).dot(n_i), mr});
      }
    auto overlap = [&](const Face<dim> &a, const Face<dim> &b, double sa, double sb) {
      const double th = std::acos(std::clamp(a.dir.dot(b.dir), -1.0, 1.0));
      return half_angle(sa * mult[a.fj] * a.m, a.a) +
             half_angle(sb * mult[b.fj] * b.m, b.a) - th;
    };
    if (code == 2)
      {
        auto valid = [&](double lam) {
          for (const auto &fs : faces)
            for (std::size_t a = 0; a < fs.size(); ++a)
              for (std::size_t b = a + 1; b < fs.size(); ++b)
                if (overlap(fs[a], fs[b], lam, lam) > 0)
                  return false;
          return true;
        };
        double lo = 0, hi = 1;
        if (!valid(1))
          {
            for (int it = 0; it < 60; ++it)
              ((valid(0.5 * (lo + hi))) ? lo : hi) = 0.5 * (lo + hi);
            for (auto &x : mult)
              x *= lo;
          }
      }
    else if (code == 1)
      for (const auto &fs : faces)
        for (std::size_t a = 0; a < fs.size(); ++a)
          for (std::size_t b = a + 1; b < fs.size(); ++b)
            if (overlap(fs[a], fs[b], 1, 1) > 0)
              {
                double lo = 0, hi = 1;
                for (int it = 0; it < 60; ++it)
                  {
                    const double mid                                = 0.5 * (lo + hi);
                    (overlap(fs[a], fs[b], mid, mid) > 0 ? hi : lo) = mid;
                  }
                mult[fs[a].fj] *= lo;
                mult[fs[b].fj] *= lo;
              }
    for (std::size_t f = 0; f < n; ++f)
      if (mult[f] != grp.properties(joints.index[f]).rmul)
        {
          grp.properties(joints.index[f]).rmul = mult[f];
          grp.reinstall(joints.index[f], P, m.walls);
        }
    return {*std::min_element(mult.begin(), mult.end()),
            *std::max_element(mult.begin(), mult.end())};
  }

  template <int dim>
  void designate_microstructure(Model<dim> &m, const JointList &joints, double phi_B,
                                double phi_G, const Distribution &gap, Random &rng)
  {
    using FJ            = FlatJointLaw<dim>;
    const std::size_t n = joints.index.size();
    if (n == 0)
      return;
    auto                    &grp = m.template typed_group<FJ>(joints.group);
    std::vector<std::size_t> order(n);
    for (std::size_t f = 0; f < n; ++f)
      order[f] = f;
    for (std::size_t f = n; f-- > 1;)
      std::swap(order[f], order[rng.index(f + 1)]);
    const auto nB = static_cast<std::size_t>(std::llround(phi_B * n));
    const auto nG = std::min(n - nB, static_cast<std::size_t>(std::llround(phi_G * n)));
    for (std::size_t r = nB; r < n; ++r)
      {
        const std::size_t k = joints.index[order[r]];
        auto             &q = grp.properties(k);
        if (r < nB + nG)
          {
            q.gap0  = rng.truncated_normal(gap); // g_o > 0 unbonds (memo Table 5)
            q.mtype = 2;
            grp.reinstall(k, m.particles, m.walls);
          }
        else
          {
            q.mtype = 3;
            FJ::unbond(grp.params, grp.state(k));
          }
      }
  }

#define DEMFEM_INSTANTIATE(dim)                                                          \
  template typename ContactGroup<dim, LinearLaw<dim>>::Rule linear_rule<dim>(            \
      const Deformability &, double);                                                    \
  template typename FlatJointLaw<dim>::Params flat_joint_params<dim>(                    \
      const MaterialParams &);                                                           \
  template typename ContactGroup<dim, FlatJointLaw<dim>>::Rule flat_joint_rule<dim>(     \
      const Deformability &, const Distribution &, const Distribution &, StrengthDraws); \
  template typename ContactGroup<dim, ParallelBondLaw<dim>>::Rule                        \
  parallel_bond_rule<dim>(const Deformability &, double, const Deformability &,          \
                          const Distribution &, const Distribution &, StrengthDraws);    \
  template typename ContactGroup<dim, ContactBondLaw<dim>>::Rule contact_bond_rule<dim>( \
      const Deformability &, double, const Distribution &, const Distribution &,         \
      StrengthDraws);                                                                    \
  template std::pair<double, double> set_radius_multipliers<dim>(                        \
      Model<dim> &, const JointList &, int, double);                                     \
  template void designate_microstructure<dim>(Model<dim> &, const JointList &, double,   \
                                              double, const Distribution &, Random &);
  DEMFEM_INSTANTIATE(2)
  DEMFEM_INSTANTIATE(3)
#undef DEMFEM_INSTANTIATE
} // namespace demfem::dem
