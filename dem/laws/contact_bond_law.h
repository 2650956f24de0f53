#pragma once
// Linear contact-bond law (PFC "linearcbond"): the linear law plus a contact
// bond of tensile and shear strength (forces). While bonded the linear springs
// also carry tension and cannot slip; the bond breaks in tension when
// Fn >= cb_tenf or in shear when |Fs| >= cb_shearf, after which the contact
// behaves exactly as the linear law (no tension, Coulomb slip). The linear
// part is LinearLaw<dim> working on the first block of our state, so that the
// unbonded behaviour cannot drift from the plain linear law.
#include "dem/engine/contact_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/linear_with_bond.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace demfem::dem
{
  template <int dim>
  struct ContactBondLaw : LinearWithBond<ContactBondLaw<dim>, LinearLaw<dim>>
  {
    using LinearWithBond<ContactBondLaw<dim>, LinearLaw<dim>>::linear_group;
    static constexpr const char *name = "contactbond";
    using Linear                      = LinearLaw<dim>;

    static constexpr BondType bond_type = BondType::contact_bond;

    /// Per-contact properties: the linear block and the bond strengths.
    struct Props
    {
      typename Linear::Props linear;        ///< kn, ks, friction, reference_gap
      double                 cb_tenf   = 0; ///< tensile strength [force]
      double                 cb_shearf = 0; ///< shear strength [force]
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
        check_range(where, "cb_tenf", this->cb_tenf, 0, inf);
        check_range(where, "cb_shearf", this->cb_shearf, 0, inf);
      }
    };

    static void prepare(Params &) {}
    /// The block with its bond strengths infinite: what the contact loop
    /// hands to `update` while bond breakage is suspended
    /// (Model::suspend_bond_breakage, docs/architecture.md).
    static Props unbreakable(Props q)
    {
      q.cb_tenf = q.cb_shearf = HUGE_VAL;
      return q;
    }
    static void derive(const Params &, Props &) {}

    static const std::vector<PropertyField<Props>> &properties()
    {
      using P                                            = Props;
      const double                                   inf = HUGE_VAL;
      static const std::vector<PropertyField<Props>> f   = [inf] {
        std::vector<PropertyField<Props>> out = lifted_linear_properties<Props>();
        out.push_back({"cb_tenf", [](const P &q) { return q.cb_tenf; },
                       [](P &q, double v) { q.cb_tenf = v; }, true, 0, inf});
        out.push_back({"cb_shearf", [](const P &q) { return q.cb_shearf; },
                       [](P &q, double v) { q.cb_shearf = v; }, true, 0, inf});
        return out;
      }();
      return f;
    }

    // state: [0, Linear::n_state) the linear block (Fn, Fss, Fst, slip flag,
    // slip energy), then the bond flag (1 bonded, 0 never bonded, -1 broken in
    // tension, -2 broken in shear).
    enum : int
    {
      s_lin  = 0,
      s_bond = Linear::n_state,
      n_state
    };

    static int state_size(const Params &) { return n_state; }

    static void install(const Params &p, const Props &q, const ContactGeometry<dim> &g,
                        double *st)
    {
      Linear::install(linear_group(), q.linear, g, st + s_lin);
      st[s_bond] = p.bonded ? 1 : 0;
    }

    static bool bonded(const double *st) { return st[s_bond] > 0; }

    static void update(const Params &, const Props &p, const ContactStep<dim> &k,
                       double *st, ContactForce &f, EventSink &events)
    {
      double *lin = st + s_lin;
      if (bonded(st))
        {
          // Bonded springs: tension allowed (Fn = kn (g - g_r) for any sign)
          // and the shear spring never slips.
          const double fn   = p.linear.kn * (k.gap - p.linear.reference_gap);
          const double fss  = lin[Linear::s_fss] - p.linear.ks * k.d_ss;
          const double fst  = lin[Linear::s_fst] - p.linear.ks * k.d_st;
          const double fs   = std::sqrt(fss * fss + fst * fst);
          int          mode = -1;
          if (fn >= p.cb_tenf)
            mode = 0;
          else if (fs >= p.cb_shearf)
            mode = 1;
          if (mode < 0)
            {
              lin[Linear::s_fn]  = fn;
              lin[Linear::s_fss] = fss;
              lin[Linear::s_fst] = fst;
              f                  = ContactForce{fn, fss, fst, 0, 0, 0};
              return;
            }
          LawEvent e;
          e.kind    = LawEvent::bond_break;
          e.element = 0;
          e.mode    = mode;
          e.size    = 2 * k.min_radius();
          e.gap     = k.gap;
          // Contact-bond strengths are forces; reported as given.
          e.strength = mode == 0 ? p.cb_tenf : p.cb_shearf;
          events.push(e);
          st[s_bond] = mode == 0 ? -1 : -2;
          // The bond is gone for this whole step: the linear law redoes the
          // step from the shear force at its beginning (no tension, Coulomb).
        }
      Linear::update(linear_group(), p.linear, k, lin, f, events);
    }

    static ContactStiffness stiffness(const Params &, const Props &q,
                                      const ContactGeometry<dim> &g, const double *st)
    {
      return Linear::stiffness(linear_group(), q.linear, g, st + s_lin);
    }

    static double strain_energy(const Params &, const Props &q, const double *st)
    {
      return Linear::strain_energy(linear_group(), q.linear, st + s_lin);
    }
  };
} // namespace demfem::dem
