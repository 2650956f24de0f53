#pragma once
// Linear parallel-bond law (PFC "linearpbond"): the linear law (no tension,
// Coulomb slip) in parallel with a parallel bond, an elastic beam of radius
// R_bar = lambda_bar min(R1, R2) carrying force and moment incrementally until
// its tensile or shear strength is exceeded (flat-joint memo §2.1.2-2.1.3,
// Eq. 56-61). The linear part is LinearLaw<dim> on the first block of our
// state; the total contact force is linear + bond.
#include "dem/engine/contact_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/linear_with_bond.h"

#include <cmath>
#include <string>
#include <vector>

namespace demfem::dem
{
  template <int dim>
  struct ParallelBondLaw : LinearWithBond<ParallelBondLaw<dim>, LinearLaw<dim>>
  {
    using LinearWithBond<ParallelBondLaw<dim>, LinearLaw<dim>>::linear_group;
    static constexpr const char *name = "parallelbond";
    using Linear                      = LinearLaw<dim>;

    static constexpr BondType bond_type = BondType::parallel_bond;

    /// Per-contact properties (memo §2.1.3): the linear block and the bond's.
    struct Props
    {
      typename Linear::Props linear;        ///< kn, ks, friction, reference_gap
      double                 pb_kn     = 0; ///< bond normal stiffness [stress/disp]
      double                 pb_ks     = 0; ///< bond shear stiffness [stress/disp]
      double                 pb_rmul   = 1; ///< radius multiplier lambda_bar
      double                 pb_mcf    = 1; ///< moment-contribution factor beta_bar
      double                 pb_ten    = 0; ///< tensile strength sigma_bar_c [stress]
      double                 pb_coh    = 0; ///< cohesion c_bar [stress]
      double                 pb_fa     = 0; ///< friction angle phi_bar [degrees]
      double                 pb_tan_fa = 0; ///< tan(phi_bar), derived
    };

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
      bool bonded = false; ///< bond the contact when installed

      void validate(const std::string &where) const
      {
        const double            inf = HUGE_VAL;
        typename Linear::Params lin;
        static_cast<typename Linear::Props &>(lin) = this->linear;
        lin.validate(where);
        check_range(where, "pb_kn", this->pb_kn, 0, inf);
        check_range(where, "pb_ks", this->pb_ks, 0, inf);
        check_range(where, "pb_rmul", this->pb_rmul, 0, inf, true, false);
        check_range(where, "pb_mcf", this->pb_mcf, 0, 1);
        check_range(where, "pb_ten", this->pb_ten, 0, inf);
        check_range(where, "pb_coh", this->pb_coh, 0, inf);
        check_range(where, "pb_fa", this->pb_fa, 0, 90, false, true);
      }
    };

    static void prepare(Params &p) { derive(p, p); }
    /// The block with its bond strengths infinite: what the contact loop
    /// hands to `update` while bond breakage is suspended
    /// (Model::suspend_bond_breakage, docs/architecture.md).
    static Props unbreakable(Props q)
    {
      q.pb_ten = q.pb_coh = HUGE_VAL;
      return q;
    }
    static void derive(const Params &, Props &q)
    {
      q.pb_tan_fa = std::tan(q.pb_fa * M_PI / 180.0);
    }

    static const std::vector<PropertyField<Props>> &properties()
    {
      using P                                            = Props;
      const double                                   inf = HUGE_VAL;
      static const std::vector<PropertyField<Props>> f   = [inf] {
        std::vector<PropertyField<Props>> out = lifted_linear_properties<Props>();
        std::vector<PropertyField<Props>> own = {
            {"pb_kn", [](const P &q) { return q.pb_kn; },
             [](P &q, double v) { q.pb_kn = v; }, true, 0, inf},
            {"pb_ks", [](const P &q) { return q.pb_ks; },
             [](P &q, double v) { q.pb_ks = v; }, true, 0, inf},
            {"pb_rmul", [](const P &q) { return q.pb_rmul; },
             [](P &q, double v) { q.pb_rmul = v; }, false, 0, inf},
            {"pb_mcf", [](const P &q) { return q.pb_mcf; },
             [](P &q, double v) { q.pb_mcf = v; }, true, 0, 1},
            {"pb_ten", [](const P &q) { return q.pb_ten; },
             [](P &q, double v) { q.pb_ten = v; }, true, 0, inf},
            {"pb_coh", [](const P &q) { return q.pb_coh; },
             [](P &q, double v) { q.pb_coh = v; }, true, 0, inf},
            {"pb_fa", [](const P &q) { return q.pb_fa; },
             [](P &q, double v) { q.pb_fa = v; }, true, 0, 89.999999}};
        out.insert(out.end(), own.begin(), own.end());
        return out;
      }();
      return f;
    }

    /// Bond state B_bar as in PFC.
    enum BondState : int
    {
      unbonded     = 0,
      broken_ten   = 1,
      broken_shear = 2,
      intact       = 3
    };

    // state: linear block, then B_bar, R_bar, bond Fn, Fss, Fst, Mt, Mbs, Mbt.
    enum : int
    {
      s_lin   = 0,
      s_state = Linear::n_state,
      s_rad,
      s_fn,
      s_fss,
      s_fst,
      s_mt,
      s_mbs,
      s_mbt,
      n_state
    };

    /// Bond cross section (memo Eq. 53-55, 57): A, I, J of a rectangle of unit
    /// thickness (2D) or of a disk (3D). J is unused in 2D (no twist).
    struct Section
    {
      double A, I, J;
    };
    static Section section(double R)
    {
      if (dim == 2)
        return {2 * R, 2.0 / 3.0 * R * R * R, 0};
      return {M_PI * R * R, 0.25 * M_PI * R * R * R * R, 0.5 * M_PI * R * R * R * R};
    }

    static int state_size(const Params &) { return n_state; }

    static void install(const Params &p, const Props &q, const ContactGeometry<dim> &g,
                        double *st)
    {
      Linear::install(linear_group(), q.linear, g, st + s_lin);
      st[s_state] = p.bonded ? intact : unbonded;
      // R_bar is fixed at installation (memo Eq. 57; R1 for ball-wall).
      st[s_rad] = q.pb_rmul * g.min_radius();
      for (int i = s_fn; i < n_state; ++i)
        st[i] = 0;
    }

    static bool bonded(const double *st) { return st[s_state] == intact; }

    static void update(const Params &, const Props &p, const ContactStep<dim> &k,
                       double *st, ContactForce &f, EventSink &events)
    {
      Linear::update(linear_group(), p.linear, k, st + s_lin, f, events);
      if (!bonded(st))
        return;
      const double  R = st[s_rad];
      const Section c = section(R);
      // Incremental bond update (PFC pbond): the bond force opposes the
      // relative motion of piece 2; opening (d_n > 0) gives tension.
      st[s_fn] += p.pb_kn * c.A * k.d_n;
      st[s_fss] -= p.pb_ks * c.A * k.d_ss;
      st[s_fst] -= p.pb_ks * c.A * k.d_st;
      if (dim == 3)
        st[s_mt] -= p.pb_ks * c.J * k.d_twist;
      st[s_mbs] -= p.pb_kn * c.I * k.d_bs;
      st[s_mbt] -= p.pb_kn * c.I * k.d_bt;

      // Maximum normal and shear stresses on the bond periphery.
      const double mb    = std::sqrt(st[s_mbs] * st[s_mbs] + st[s_mbt] * st[s_mbt]);
      const double fs    = std::sqrt(st[s_fss] * st[s_fss] + st[s_fst] * st[s_fst]);
      const double sig   = st[s_fn] / c.A;
      const double sigma = sig + p.pb_mcf * mb * R / c.I;
      double       tau   = fs / c.A;
      if (dim == 3)
        tau += p.pb_mcf * std::fabs(st[s_mt]) * R / c.J;
      int    mode     = -1;
      double strength = 0;
      if (sigma > p.pb_ten)
        {
          mode     = 0;
          strength = p.pb_ten;
        }
      else
        {
          // Mohr-Coulomb shear strength; compression (sig < 0) strengthens.
          const double tauc = p.pb_coh - sig * p.pb_tan_fa;
          if (tau > tauc)
            {
              mode     = 1;
              strength = tauc;
            }
        }
      if (mode >= 0)
        {
          LawEvent e;
          e.kind     = LawEvent::bond_break;
          e.element  = 0;
          e.mode     = mode;
          e.size     = 2 * R;
          e.gap      = k.gap;
          e.strength = strength;
          events.push(e);
          st[s_state] = mode == 0 ? broken_ten : broken_shear;
          for (int i = s_fn; i < n_state; ++i)
            st[i] = 0;
          return;
        }
      f.Fn += st[s_fn];
      f.Fss += st[s_fss];
      f.Fst += st[s_fst];
      f.Mt += st[s_mt];
      f.Mbs += st[s_mbs];
      f.Mbt += st[s_mbt];
    }

    /// Bond force and moment (contact-plane components) for output.
    static ContactForce bond_force(const double *st)
    {
      return {st[s_fn], st[s_fss], st[s_fst], st[s_mt], st[s_mbs], st[s_mbt]};
    }

    static ContactStiffness stiffness(const Params &, const Props &p,
                                      const ContactGeometry<dim> &g, const double *st)
    {
      ContactStiffness s = Linear::stiffness(linear_group(), p.linear, g, st + s_lin);
      if (bonded(st))
        {
          const Section c = section(st[s_rad]);
          s.kn += p.pb_kn * c.A;
          s.ks += p.pb_ks * c.A;
          s.kb += p.pb_kn * c.I;
          s.kt += p.pb_ks * c.J;
        }
      return s;
    }

    static double strain_energy(const Params &, const Props &p, const double *st)
    {
      double        e   = Linear::strain_energy(linear_group(), p.linear, st + s_lin);
      const Section c   = section(st[s_rad]);
      auto          add = [&e](double f2, double k) {
        if (k > 0)
          e += 0.5 * f2 / k;
      };
      add(st[s_fn] * st[s_fn], p.pb_kn * c.A);
      add(st[s_fss] * st[s_fss] + st[s_fst] * st[s_fst], p.pb_ks * c.A);
      add(st[s_mbs] * st[s_mbs] + st[s_mbt] * st[s_mbt], p.pb_kn * c.I);
      add(st[s_mt] * st[s_mt], p.pb_ks * c.J);
      return e;
    }
  };
} // namespace demfem::dem
