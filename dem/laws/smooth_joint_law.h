#pragma once
// Smooth-joint law (PFC "smoothjoint", seed 001): a planar, optionally bonded
// interface of fixed global orientation n_j between the two pieces. The
// relative displacement is resolved along the joint (seed Eq. 3-4), not along
// the contact normal, so that particles on either side of a joint slide along
// the joint plane regardless of their contact orientations. Unbonded: linear
// elastic, Coulomb slip with dilation (Eq. 7-12); bonded: linear elastic until
// the tensile or Mohr-Coulomb shear strength is exceeded (Eq. 13-15). No
// moment is carried.
#include "dem/engine/contact_law.h"

#include <cmath>
#include <string>
#include <vector>

namespace demfem::dem
{
  template <int dim>
  struct SmoothJointLaw
  {
    static constexpr const char *name = "smoothjoint";

    static constexpr BondType bond_type = BondType::smooth_joint;

    /// Per-contact properties (seed Table 2).
    struct Props
    {
      double sj_kn     = 0; ///< normal stiffness [stress/disp]
      double sj_ks     = 0; ///< shear stiffness [stress/disp]
      double sj_fric   = 0; ///< friction coefficient mu
      double sj_da     = 0; ///< dilation angle psi [degrees]
      double sj_ten    = 0; ///< tensile strength sigma_c [stress]
      double sj_coh    = 0; ///< cohesion c [stress]
      double sj_fa     = 0; ///< friction angle phi [degrees]
      double sj_rmul   = 1; ///< radius multiplier lambda
      double sj_tan_fa = 0; ///< tan(phi), derived
      double sj_tan_da = 0; ///< tan(psi), derived
    };

    /// Group-wide: the joint plane and the modes.
    struct Params : Props
    {
      /// A copy with the group constants derived (what Model::add_law
      /// stores), for calling the law directly (tests, probes).
      Params prepared() const
      {
        Params c = *this;
        prepare(c);
        return c;
      }
      double dip      = 0;     ///< dip angle theta_p [degrees]
      double ddir     = 0;     ///< dip direction theta_d [degrees] (3D)
      bool   sj_large = false; ///< large-strain mode S_l
      bool   bonded   = false; ///< bond the joint when installed (S_j = 3)

      void validate(const std::string &where) const
      {
        const double inf = HUGE_VAL;
        check_range(where, "sj_kn", this->sj_kn, 0, inf);
        check_range(where, "sj_ks", this->sj_ks, 0, inf);
        check_range(where, "sj_fric", this->sj_fric, 0, inf);
        // Table 2 allows [0, inf) but tan(psi) is meaningless from 90 deg on.
        check_range(where, "sj_da", this->sj_da, 0, 90, false, true);
        check_range(where, "sj_ten", this->sj_ten, 0, inf);
        check_range(where, "sj_coh", this->sj_coh, 0, inf);
        check_range(where, "sj_fa", this->sj_fa, 0, 90, false, true);
        // Table 2 allows 0, but then the joint has no area (Eq. 2).
        check_range(where, "sj_rmul", this->sj_rmul, 0, inf, true, false);
        // Ranges of seed Table 2, taken literally.
        check_range(where, "dip", dip, 0, 360);
        check_range(where, "ddir", ddir, 0, 180);
      }
    };

    static void prepare(Params &p) { derive(p, p); }
    /// The block with its bond strengths infinite: what the contact loop
    /// hands to `update` while bond breakage is suspended
    /// (Model::suspend_bond_breakage, docs/architecture.md).
    static Props unbreakable(Props q)
    {
      q.sj_ten = q.sj_coh = HUGE_VAL;
      return q;
    }
    static void derive(const Params &, Props &q)
    {
      q.sj_tan_fa = std::tan(deg(q.sj_fa));
      q.sj_tan_da = std::tan(deg(q.sj_da));
    }

    static const std::vector<PropertyField<Props>> &properties()
    {
      using P                                        = Props;
      const double                                   inf = HUGE_VAL;
      static const std::vector<PropertyField<Props>> f   = {
          {"sj_kn", [](const P &q) { return q.sj_kn; }, [](P &q, double v) { q.sj_kn = v; },
           true, 0, inf},
          {"sj_ks", [](const P &q) { return q.sj_ks; }, [](P &q, double v) { q.sj_ks = v; },
           true, 0, inf},
          {"sj_fric", [](const P &q) { return q.sj_fric; },
           [](P &q, double v) { q.sj_fric = v; }, true, 0, inf},
          {"sj_da", [](const P &q) { return q.sj_da; }, [](P &q, double v) { q.sj_da = v; },
           true, 0, 89.999999},
          {"sj_ten", [](const P &q) { return q.sj_ten; },
           [](P &q, double v) { q.sj_ten = v; }, true, 0, inf},
          {"sj_coh", [](const P &q) { return q.sj_coh; },
           [](P &q, double v) { q.sj_coh = v; }, true, 0, inf},
          {"sj_fa", [](const P &q) { return q.sj_fa; }, [](P &q, double v) { q.sj_fa = v; },
           true, 0, 89.999999},
          {"sj_rmul", [](const P &q) { return q.sj_rmul; },
           [](P &q, double v) { q.sj_rmul = v; }, false, 0, inf}};
      return f;
    }

    /// Joint bond state S_j (Table 2).
    enum BondState : int
    {
      unbonded     = 0,
      broken_ten   = 1,
      broken_shear = 2,
      intact       = 3
    };

    // state: joint normal n_j (global, oriented from surface 1 to surface 2
    // for this contact), joint gap g_j, accumulated normal displacement
    // delta_n (Eq. 4, closing positive), accumulated shear displacement
    // delta_s (global), Fn (tension positive), Fs (global), S_j, slip flag,
    // slip energy, joint radius R.
    static constexpr int s_nj    = 0;
    static constexpr int s_gap   = dim;
    static constexpr int s_un    = dim + 1;
    static constexpr int s_us    = dim + 2;
    static constexpr int s_fn    = 2 * dim + 2;
    static constexpr int s_fs    = 2 * dim + 3;
    static constexpr int s_state = 3 * dim + 3;
    static constexpr int s_slip  = 3 * dim + 4;
    static constexpr int s_eslip = 3 * dim + 5;
    static constexpr int s_rad   = 3 * dim + 6;
    static constexpr int n_state = 3 * dim + 7;

    static int state_size(const Params &) { return n_state; }

    static double deg(double a) { return a * M_PI / 180.0; }

    /// Joint unit normal from dip and dip direction (seed Eq. 1).
    static Vec<dim> joint_normal(const Params &p)
    {
      Vec<dim>     nj;
      const double tp = deg(p.dip), td = deg(p.ddir);
      if constexpr (dim == 2)
        nj << std::sin(tp), std::cos(tp);
      else
        nj << std::sin(tp) * std::sin(td), std::sin(tp) * std::cos(td), std::cos(tp);
      return nj;
    }

    /// Joint cross-section area. Seed Eq. 2 gives A = pi R^2; PFC2D models
    /// disks of unit thickness, so in 2D we use the strip A = 2 R * 1
    /// (consistent with the other 2D laws).
    static double area(double R) { return dim == 2 ? 2 * R : M_PI * R * R; }

    static Vec<dim> vec(const double *st, int off)
    {
      return Eigen::Map<const Vec<dim>>(st + off);
    }
    static void set_vec(double *st, int off, const Vec<dim> &v)
    {
      Eigen::Map<Vec<dim>>(st + off) = v;
    }

    static void install(const Params &p, const Props &q, const ContactGeometry<dim> &g,
                        double *st)
    {
      for (int i = 0; i < n_state; ++i)
        st[i] = 0;
      // Piece 2 lies in surface 2 iff n_c . n_j >= 0 (seed "Kinematic
      // Variables"); otherwise we flip n_j for this contact so that it always
      // points from piece 1's surface into piece 2's and the rest of the law
      // needs no case distinction.
      Vec<dim> nj = joint_normal(p);
      if (g.n.dot(nj) < 0)
        nj = -nj;
      set_vec(st, s_nj, nj);
      st[s_state] = p.bonded ? intact : unbonded;
      st[s_rad]   = q.sj_rmul * g.min_radius(); // seed Eq. 2
    }

    static bool bonded(const double *st) { return st[s_state] == intact; }

    static bool active(const Params &p, const Props &, const double *st, double gap)
    {
      return !p.sj_large || bonded(st) || gap < 0;
    }

    static bool deletable(const Params &p, const Props &, const double *st, double gap)
    {
      return p.sj_large && !bonded(st) && gap >= 0;
    }

    static void update(const Params &, const Props &p, const ContactStep<dim> &k,
                       double *st, ContactForce &f, EventSink &events)
    {
      const Vec<dim> nj = vec(st, s_nj);
      // Relative displacement increment of piece 2 (global), memo Eq. 11.
      Vec<dim> dd = k.d_n * k.n + k.d_st * k.t;
      if constexpr (dim == 3)
        dd += k.d_ss * k.s;
      // Resolve along the joint (seed Eq. 3) and accumulate (Eq. 4);
      // dn > 0 opens the joint.
      const double   dn = dd.dot(nj);
      const Vec<dim> ds = dd - dn * nj;
      st[s_un] -= dn;
      set_vec(st, s_us, vec(st, s_us) + ds);
      const double g0 = st[s_gap], g1 = g0 + dn;
      st[s_gap] = g1;

      // Elastic fraction of the increment: all of it while bonded; unbonded,
      // only the part during which g_j < 0, g_j varying linearly within the
      // step (the interpolation of memo Eq. 33, extended to opening steps).
      const bool is_bonded = bonded(st);
      double     alpha     = 1;
      if (!is_bonded)
        {
          if (g0 >= 0 && g1 >= 0)
            alpha = 0;
          else if (g0 >= 0) // closing across g_j = 0
            alpha = g1 / (g1 - g0);
          else if (g1 >= 0) // opening across g_j = 0
            alpha = g0 / (g0 - g1);
        }
      const double   dne = alpha * dn;
      const Vec<dim> dse = alpha * ds;

      const double   A   = area(st[s_rad]);
      const double   knA = p.sj_kn * A, ksA = p.sj_ks * A;
      const double   fn_o  = st[s_fn];
      const Vec<dim> fs_o  = vec(st, s_fs);
      double         fn    = fn_o + knA * dne; // Eq. 7, tension positive
      const Vec<dim> fs_t  = fs_o - ksA * dse; // Eq. 8, trial shear force
      const double   fs_tn = fs_t.norm();
      const double   fsmu  = -p.sj_fric * fn; // Eq. 9
      Vec<dim>       fs    = fs_t;
      bool           slip  = false;
      // Coulomb limit, Eq. 10-11 (slip iff the trial force exceeds it).
      auto coulomb = [&]() {
        if (fs_tn > fsmu)
          {
            slip = true;
            fs   = fs_tn > 0 ? Vec<dim>(fs_t * (fsmu / fs_tn)) : Vec<dim>::Zero();
          }
      };

      if (is_bonded)
        {
          // Eq. 13 with tau_c = c - (Fn / A) tan(phi).
          const double tauc = p.sj_coh - fn / A * p.sj_tan_fa;
          int          mode = -1;
          if (fn >= p.sj_ten * A)
            {
              mode        = 0;
              st[s_state] = broken_ten;
              fn          = 0; // Eq. 14
              fs.setZero();
            }
          else if (fs_tn >= tauc * A)
            {
              mode        = 1;
              st[s_state] = broken_shear;
              if (fn > 0) // broken in shear while in tension: Eq. 14
                {
                  fn = 0;
                  fs.setZero();
                }
              else // in compression: Coulomb limit, no dilation
                coulomb();
            }
          // else intact: Fs = Fs* (Eq. 15)
          if (mode >= 0)
            {
              LawEvent e;
              e.kind     = LawEvent::bond_break;
              e.element  = 0;
              e.mode     = mode;
              e.size     = 2 * st[s_rad];
              e.gap      = g1;
              e.strength = mode == 0 ? p.sj_ten : tauc;
              // The crack lies in the joint plane (seed 001), not normal to
              // the contact.
              e.has_normal = true;
              for (int a = 0; a < dim; ++a)
                e.normal[a] = st[s_nj + a];
              events.push(e);
            }
        }
      else if (g1 >= 0 || fn >= 0)
        {
          // Open unbonded joint: it transmits nothing.
          fn = 0;
          fs.setZero();
        }
      else
        {
          coulomb();
          // Dilation (Eq. 12). The slip displacement of this step is
          // (|Fs*| - Fs^mu) / (ks A); dilation tries to open the joint by
          // tan(psi) times it, and the normal spring resists, adding
          // kn A tan(psi) (|Fs*| - Fs^mu) / (ks A) of COMPRESSION (the seed
          // writes "+" for the magnitude). With Fn tension positive the
          // normal force therefore decreases.
          if (slip && p.sj_ks > 0)
            fn -= (fs_tn - fsmu) / p.sj_ks * p.sj_kn * p.sj_tan_da;
        }

      // Slip energy (Eq. 17, with the A the seed omits): slip part of the
      // increment = elastic-range increment - elastic part -(Fs - Fs_o)/(ks A);
      // dissipation = -(average force) . (slip), positive.
      if (slip && ksA > 0)
        {
          const Vec<dim> us = dse + (fs - fs_o) / ksA;
          st[s_eslip] -= 0.5 * (fs_o + fs).dot(us);
        }
      if (slip != (st[s_slip] != 0))
        {
          LawEvent e;
          e.kind = slip ? LawEvent::slip_start : LawEvent::slip_end;
          e.gap  = g1;
          events.push(e);
          st[s_slip] = slip ? 1 : 0;
        }
      st[s_fn] = fn;
      set_vec(st, s_fs, fs);

      // Contact force on piece 2 (Eq. 5-6): F = -Fn n_j + Fs, projected on
      // the contact plane (F_c = -Fn_c n + Fss s + Fst t).
      const Vec<dim> F = -fn * nj + fs;
      f                = ContactForce{};
      f.Fn             = -F.dot(k.n);
      f.Fst            = F.dot(k.t);
      if constexpr (dim == 3)
        f.Fss = F.dot(k.s);
    }

    static ContactStiffness stiffness(const Params &, const Props &p,
                                      const ContactGeometry<dim> &, const double *st)
    {
      const double A = area(st[s_rad]);
      return {p.sj_kn * A, p.sj_ks * A, 0, 0};
    }

    /// Strain energy, Eq. 16 made dimensionally consistent: the seed's
    /// stiffnesses are per unit area, so the spring stiffnesses are kn A, ks A.
    static double strain_energy(const Params &, const Props &p, const double *st)
    {
      const double A = area(st[s_rad]);
      double       e = 0;
      if (p.sj_kn > 0)
        e += 0.5 * st[s_fn] * st[s_fn] / (p.sj_kn * A);
      if (p.sj_ks > 0)
        e += 0.5 * vec(st, s_fs).squaredNorm() / (p.sj_ks * A);
      return e;
    }

    static double slip_energy(const Params &, const Props &, const double *st)
    {
      return st[s_eslip];
    }
  };
} // namespace demfem::dem
