#pragma once
// Linear contact law (PFC "linear"): no tension, linear normal and shear
// springs (force/displacement), Coulomb slip. Also the group that new
// contacts of every material receive. Serves as the template for the other
// laws (see dem/contact_law.h for the contract).
#include "dem/contact_law.h"

#include <cmath>
#include <string>

namespace demfem::dem
{
  template <int dim>
  struct LinearLaw
  {
    static constexpr const char *name = "linear";

    struct Params
    {
      double kn            = 0; ///< normal stiffness [N/m]
      double ks            = 0; ///< shear stiffness [N/m]
      double friction      = 0; ///< friction coefficient mu
      double reference_gap = 0; ///< springs engage when gap < reference gap

      void validate(const std::string &where) const
      {
        const double inf = HUGE_VAL;
        check_range(where, "kn", kn, 0, inf);
        check_range(where, "ks", ks, 0, inf);
        check_range(where, "friction", friction, 0, inf);
        check_range(where, "reference_gap", reference_gap, -inf, inf, true, true);
      }
    };

    /// Stiffnesses from the deformability method (memo Eq. 40 analogue for
    /// the linear model): kn = A E*/L with A the cross section of the
    /// equivalent beam of radius min(R1, R2), ks = kn / kappa*.
    static Params deformability(double emod, double kratio, double friction,
                                const ContactGeometry<dim> &g)
    {
      const double r = g.min_radius();
      const double A = (dim == 2 ? 2 * r : M_PI * r * r);
      Params p;
      p.kn       = A * emod / g.length();
      p.ks       = kratio > 0 ? p.kn / kratio : 0;
      p.friction = friction;
      return p;
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

    static void install(const Params &, const ContactGeometry<dim> &, double *st)
    {
      for (int i = 0; i < n_state; ++i)
        st[i] = 0;
    }

    static bool active(const Params &p, const double *, double gap)
    {
      return gap < p.reference_gap;
    }

    static bool deletable(const Params &p, const double *, double gap)
    {
      return gap >= p.reference_gap;
    }

    static void update(const Params &p, const ContactStep<dim> &k, double *st,
                       ContactForce &f, EventSink &events)
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

    static ContactStiffness stiffness(const Params &p, const ContactGeometry<dim> &,
                                      const double *)
    {
      return {p.kn, p.ks, 0, 0};
    }

    static double strain_energy(const Params &p, const double *st)
    {
      double e = 0;
      if (p.kn > 0)
        e += 0.5 * st[s_fn] * st[s_fn] / p.kn;
      if (p.ks > 0)
        e += 0.5 * (st[s_fss] * st[s_fss] + st[s_fst] * st[s_fst]) / p.ks;
      return e;
    }

    static double slip_energy(const Params &, const double *st) { return st[s_eslip]; }
  };
} // namespace demfem::dem
