#pragma once
// Linear contact law (PFC "linear"): no tension, linear normal and shear
// springs (force/displacement), Coulomb slip. Also the group that new
// contacts of every material receive. Serves as the template for the other
// laws (see dem/engine/contact_law.h for the contract).
#include "dem/engine/contact_law.h"

#include <cmath>
#include <string>
#include <vector>

namespace demfem::dem
{
  template <int dim>
  struct LinearLaw
  {
    static constexpr const char *name = "linear";

    static constexpr BondType bond_type = BondType::none;

    /// Per-contact properties (PFC lin_kn, lin_ks, lin_fric, rgap).
    struct Props
    {
      double kn            = 0; ///< normal stiffness [N/m]
      double ks            = 0; ///< shear stiffness [N/m]
      double friction      = 0; ///< friction coefficient mu
      double reference_gap = 0; ///< springs engage when gap < reference gap
    };

    /// No group-wide parameter: the Props part is the default block.
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
      void validate(const std::string &where) const
      {
        const double inf = HUGE_VAL;
        check_range(where, "kn", this->kn, 0, inf);
        check_range(where, "ks", this->ks, 0, inf);
        check_range(where, "friction", this->friction, 0, inf);
        check_range(where, "reference_gap", this->reference_gap, -inf, inf, true, true);
      }
    };

    static void prepare(Params &) {}
    /// No bond: the block as it is (Model::suspend_bond_breakage).
    static const Props &unbreakable(const Props &q) { return q; }

    static void derive(const Params &, Props &) {}

    static const std::vector<PropertyField<Props>> &properties()
    {
      using P                                            = Props;
      const double                                   inf = HUGE_VAL;
      static const std::vector<PropertyField<Props>> f   = {
          {"kn", [](const P &q) { return q.kn; }, [](P &q, double v) { q.kn = v; }, true, 0,
           inf},
          {"ks", [](const P &q) { return q.ks; }, [](P &q, double v) { q.ks = v; }, true, 0,
           inf},
          {"fric", [](const P &q) { return q.friction; },
           [](P &q, double v) { q.friction = v; }, true, 0, inf},
          {"rgap", [](const P &q) { return q.reference_gap; },
           [](P &q, double v) { q.reference_gap = v; }, false, -inf, inf}};
      return f;
    }

    // state: [0] Fn, [1] Fss, [2] Fst, [3] slipping flag, [4] slip energy
    enum : int
    {
      s_fn,
      s_fss,
      s_fst,
      s_slip,
      s_eslip,
      n_state
    };

    static int state_size(const Params &) { return n_state; }

    static void install(const Params &, const Props &, const ContactGeometry<dim> &,
                        double *st)
    {
      for (int i = 0; i < n_state; ++i)
        st[i] = 0;
    }

    static bool active(const Params &, const Props &p, const double *, double gap)
    {
      return gap < p.reference_gap;
    }

    static bool deletable(const Params &, const Props &p, const double *, double gap)
    {
      return gap >= p.reference_gap;
    }

    static void update(const Params &, const Props &p, const ContactStep<dim> &k,
                       double *st, ContactForce &f, EventSink &events)
    {
      // Normal: compression only, Fn > 0 would be tension.
      const double overlap = k.gap - p.reference_gap;
      const double fn      = overlap < 0 ? p.kn * overlap : 0.0;
      // Shear: incremental, opposing relative shear motion of piece 2.
      const double fso_s = st[s_fss], fso_t = st[s_fst];
      // A separated contact carries no shear force (it is inactive).
      double fss = overlap < 0 ? fso_s - p.ks * k.d_ss : 0.0;
      double fst = overlap < 0 ? fso_t - p.ks * k.d_st : 0.0;
      const double limit = -p.friction * fn;
      const double trial = std::sqrt(fss * fss + fst * fst);
      const bool   slip  = overlap < 0 && trial > limit;
      if (slip)
        {
          const double scale = trial > 0 ? limit / trial : 0.0;
          fss *= scale;
          fst *= scale;
          // Slip part of the increment = total - elastic (elastic = -dF/ks);
          // dissipated energy = average shear force times slip displacement.
          if (p.ks > 0)
            {
              const double us = k.d_ss + (fss - fso_s) / p.ks;
              const double ut = k.d_st + (fst - fso_t) / p.ks;
              st[s_eslip] -= 0.5 * ((fso_s + fss) * us + (fso_t + fst) * ut);
            }
        }
      if (slip != (st[s_slip] != 0))
        {
          LawEvent e;
          e.kind = slip ? LawEvent::slip_start : LawEvent::slip_end;
          events.push(e);
          st[s_slip] = slip ? 1 : 0;
        }
      st[s_fn]  = fn;
      st[s_fss] = fss;
      st[s_fst] = fst;
      f         = ContactForce{fn, fss, fst, 0, 0, 0};
    }

    static ContactStiffness stiffness(const Params &, const Props &p,
                                      const ContactGeometry<dim> &, const double *)
    {
      return {p.kn, p.ks, 0, 0};
    }

    static double strain_energy(const Params &, const Props &p, const double *st)
    {
      double e = 0;
      if (p.kn > 0)
        e += 0.5 * st[s_fn] * st[s_fn] / p.kn;
      if (p.ks > 0)
        e += 0.5 * (st[s_fss] * st[s_fss] + st[s_fst] * st[s_fst]) / p.ks;
      return e;
    }

    static double slip_energy(const Params &, const Props &, const double *st)
    {
      return st[s_eslip];
    }
  };

  /// The linear block's properties (same keywords as LinearLaw::properties)
  /// for a law whose Props holds it as its `linear` member.
  template <class Outer>
  std::vector<PropertyField<Outer>> lifted_linear_properties()
  {
    using P          = Outer;
    const double inf = HUGE_VAL;
    return {{"kn", [](const P &q) { return q.linear.kn; },
             [](P &q, double v) { q.linear.kn = v; }, true, 0, inf},
            {"ks", [](const P &q) { return q.linear.ks; },
             [](P &q, double v) { q.linear.ks = v; }, true, 0, inf},
            {"fric", [](const P &q) { return q.linear.friction; },
             [](P &q, double v) { q.linear.friction = v; }, true, 0, inf},
            {"rgap", [](const P &q) { return q.linear.reference_gap; },
             [](P &q, double v) { q.linear.reference_gap = v; }, false, -inf, inf}};
  }
} // namespace demfem::dem
