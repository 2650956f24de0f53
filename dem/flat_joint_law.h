#pragma once
// Flat-joint contact law (PFC "flatjoint", memo 000 §1.4-1.13).
//
// The interface between the two notional surfaces (a segment of width 2R in
// 2D, a disk of radius R in 3D) is cut into elements (memo Eq. 13, 16-17).
// Each element is bonded (B = 3) or unbonded (B = 0, 1 broke in tension,
// 2 broke in shear) and carries a normal force, a shear force and (2D) a
// bending moment; the contact force and moment are their statically
// equivalent resultant at the contact location (memo Eq. 23-24).
//
// Conventions (see dem/contact_law.h): everything is in contact-plane
// components, Fn > 0 is tension, the force -Fn n + Fss s + Fst t and the
// moment Mt n + Mbs s + Mbt t act on piece 2.
//
// Interface gap. 3D (memo Eq. 21): g(s, t) = g_s + (t xi_s - s xi_t)|theta_b|
// = g_s + t theta_bs - s theta_bt. 2D: the interface is the line r = rho t,
// and Eq. 21 with s = 0 gives g(rho) = g_s + rho theta_bs = g_s - rho theta_bk
// (theta_bk = -theta_bs): with t = k x n a positive theta_bk (piece 2 turning
// counter-clockwise) opens the side at negative rho. This is memo Eq. 14 with
// gamma = R - rho. Hence the element end "a" of memo Eq. 44 (zeta = 0) is the
// end with the larger rho and zeta runs toward smaller rho, i.e. along -t =
// the direction of n x k; the arm r = zeta - rbar of Eq. 45 is then the
// coordinate along n x k, and M_b = -int r sigma dA (Eq. 47-49) is exactly the
// moment about +z, with respect to the element centroid, of the element
// force -sigma n dA on piece 2. A force -Fn n at rho t contributes rho Fn
// about +z (t x n = -k), so the 2D resultant about +z is sum(rho Fn + Mb)
// (memo Eq. 24) and, since s = -k, Mbs = -sum(rho Fn + Mb).
// Check (pure bending): moment about z = -kn (2/3) R^3 theta_bk (resisting).
#include "dem/contact_law.h"

#include <array>
#include <cmath>
#include <string>

namespace demfem::dem
{
  template <int dim>
  struct FlatJointLaw
  {
    static constexpr const char *name = "flatjoint";

    /// Memo Table 5 (names of the memo keywords without the "fj_" prefix).
    struct Params
    {
      int    Nr     = 2;     ///< elements in radial direction (2D: elements)
      int    Nal    = 4;     ///< elements in circumferential direction (3D only)
      double rmul   = 1.0;   ///< radius multiplier lambda (memo Eq. 30)
      double gap0   = 0.0;   ///< initial surface gap g_o
      double kn     = 0.0;   ///< normal stiffness [stress/disp]
      double ks     = 0.0;   ///< shear stiffness [stress/disp]
      double fric   = 0.0;   ///< friction coefficient mu
      double ten    = 0.0;   ///< tensile strength sigma_c [stress]
      double coh    = 0.0;   ///< cohesion c [stress]
      double fa     = 0.0;   ///< friction angle phi [degrees]
      bool   bonded = false; ///< install with all elements bonded (if gap0 = 0)

      void validate(const std::string &where) const
      {
        const double inf = HUGE_VAL;
        check_range(where, "Nr", Nr, 1, inf);
        if (dim == 3)
          check_range(where, "Nal", Nal, 3, inf);
        check_range(where, "rmul", rmul, 0, inf, true, false);
        check_range(where, "gap0", gap0, 0, inf);
        check_range(where, "kn", kn, 0, inf);
        check_range(where, "ks", ks, 0, inf);
        check_range(where, "fric", fric, 0, inf);
        check_range(where, "ten", ten, 0, inf);
        check_range(where, "coh", coh, 0, inf);
        check_range(where, "fa", fa, 0, 90, false, true);
      }
    };

    /// Result of the deformability method.
    struct Deformability
    {
      double kn = 0, ks = 0;
    };

    /// Memo Eq. 40: kn = E*/L, ks = kn/kappa* (L = R1 + R2, or R1 ball-wall);
    /// kappa* = 0 gives ks = 0 (memo Table 5 note 2).
    static Deformability deformability(double emod, double kratio,
                                       const ContactGeometry<dim> &g)
    {
      const double inf = HUGE_VAL;
      check_range("flatjoint deformability", "emod", emod, 0, inf);
      check_range("flatjoint deformability", "kratio", kratio, 0, inf);
      check_range("flatjoint deformability", "L", g.length(), 0, inf, true, false);
      Deformability d;
      d.kn = emod / g.length();
      d.ks = kratio > 0 ? d.kn / kratio : 0.0;
      return d;
    }

    // ---- state layout -----------------------------------------------------
    // header: R, g_s, delta_ss, delta_st, theta_bs, theta_bt (memo Eq. 15/22)
    enum : int
    {
      h_R,
      h_gs,
      h_dss,
      h_dst,
      h_tbs,
      h_tbt,
      n_head
    };
    // per element: bond state, slip flag, forces, slip energy, centroid gap
    // at the end of the previous step (g_0 of Eq. 33), fixed geometry.
    enum : int
    {
      e_B,
      e_slip,
      e_fn,
      e_fss,
      e_fst,
      e_mb,
      e_eslip,
      e_gap,
      e_area,
      e_rs,
      e_rt,
      n_elem
    };

    static int element_count(const Params &p) { return dim == 2 ? p.Nr : p.Nr * p.Nal; }
    static int state_size(const Params &p) { return n_head + n_elem * element_count(p); }

    static double       *elem(double *st, int e) { return st + n_head + n_elem * e; }
    static const double *elem(const double *st, int e)
    {
      return st + n_head + n_elem * e;
    }

    /// Element area and centroid (r_s, r_t) for radius R: memo Eq. 13 (2D),
    /// Eq. 16-17 (3D); e is 0-based.
    static void element_geometry(const Params &p, double R, int e, double &A, double &rs,
                                 double &rt)
    {
      if (dim == 2)
        {
          const int Nr = p.Nr;
          A            = 2 * R / Nr;
          rs           = 0;
          rt           = R * (-2.0 * (e + 1) + 1 + Nr) / Nr; // rho^(e), Eq. 13
        }
      else
        {
          const int    I = e / p.Nal, J = e - I * p.Nal;
          const double dr = R / p.Nr, da = 2 * M_PI / p.Nal;
          const double r1 = I * dr, r2 = (I + 1) * dr;
          const double a1 = J * da, a2 = (J + 1) * da;
          const double radial = (r2 * r2 * r2 - r1 * r1 * r1) / (r2 * r2 - r1 * r1);
          A                   = 0.5 * (a2 - a1) * (r2 * r2 - r1 * r1);
          rs = 2.0 / 3.0 * (std::sin(a2) - std::sin(a1)) / (a2 - a1) * radial;
          rt = 2.0 / 3.0 * (std::cos(a1) - std::cos(a2)) / (a2 - a1) * radial;
        }
    }

    /// Interface gap at (r_s, r_t) (memo Eq. 21; 2D Eq. 14 as derived above).
    static double interface_gap(const double *st, double rs, double rt)
    {
      if (dim == 2)
        return st[h_gs] + rt * st[h_tbs];
      // memo Eq. 21-22: g = g_s + (t xi_s - s xi_t)|theta_b| with
      // xi = theta_b/|theta_b|; the norm cancels, leaving the expression
      // below (no sqrt or division in the hot loop). For |theta_b| <= 1e-12,
      // where the memo sets xi = 0, the difference is below 1e-12 R.
      return st[h_gs] + rt * st[h_tbs] - rs * st[h_tbt];
    }

    /// 2D exact element integrals, memo Eq. 44-49 (t = 1): normal force
    /// Fn = int sigma dzeta and bending moment Mb = -int (zeta - rbar) sigma
    /// dzeta for a gap varying linearly from ga (zeta = 0) to gb (zeta = 2 rbar).
    static void integrate_2d(double kn, double rbar, double ga, double gb, bool bonded,
                             double &Fn, double &Mb)
    {
      const double full_f = kn * rbar * (ga + gb);
      const double full_m = kn * rbar * rbar * (ga - gb) / 3.0;
      if (ga * gb < 0) // case 1: sign change inside the element (Eq. 46-47)
        {
          if (bonded)
            {
              Fn = full_f;
              Mb = full_m;
            }
          else if (ga < 0)
            {
              const double d = gb - ga;
              Fn             = kn * rbar * ga * ga / (ga - gb);
              Mb             = kn * rbar * rbar * ga * ga * (ga - 3 * gb) / (3 * d * d);
            }
          else
            {
              const double d = gb - ga;
              Fn             = kn * rbar * gb * gb / (gb - ga);
              Mb =
                  kn * rbar * rbar * (-d * d * d - ga * ga * (ga - 3 * gb)) / (3 * d * d);
            }
        }
      else if (ga >= 0 && gb >= 0) // case 2 (Eq. 48)
        {
          Fn = bonded ? full_f : 0.0;
          Mb = bonded ? full_m : 0.0;
        }
      else // case 3 (Eq. 49)
        {
          Fn = full_f;
          Mb = full_m;
        }
    }

    /// Element normal force and bending moment from the current gap field
    /// (memo step 1 and 3): 2D exact (Eq. 44-49), 3D Eq. 50 (Mb = 0).
    static void normal_and_bending(const Params &p, const double *st, const double *el,
                                   bool bonded, double &Fn, double &Mb)
    {
      if (dim == 2)
        {
          const double rbar = st[h_R] / p.Nr;
          const double rho  = el[e_rt];
          // end a = larger rho (see the header comment)
          const double ga = interface_gap(st, 0, rho + rbar);
          const double gb = interface_gap(st, 0, rho - rbar);
          integrate_2d(p.kn, rbar, ga, gb, bonded, Fn, Mb);
        }
      else
        {
          const double g = interface_gap(st, el[e_rs], el[e_rt]);
          Fn             = (!bonded && g >= 0) ? 0.0 : p.kn * g * el[e_area];
          Mb             = 0.0;
        }
    }

    /// Crack size (fistPkg §3.4, memo footnote 3): 2D element length,
    /// 3D twice the radius of the disk of equal area.
    static double element_size(const Params &p, const double *st, const double *el)
    {
      return dim == 2 ? 2 * st[h_R] / p.Nr : 2 * std::sqrt(el[e_area] / M_PI);
    }

    // ---- contract -----------------------------------------------------------
    static void install(const Params &p, const ContactGeometry<dim> &g, double *st)
    {
      for (int i = 0, n = state_size(p); i < n; ++i)
        st[i] = 0;                                   // memo Eq. 29, 31
      st[h_R]             = p.rmul * g.min_radius(); // memo Eq. 30
      st[h_gs]            = p.gap0;                  // memo Eq. 31
      const bool bond_all = p.bonded && p.gap0 == 0; // Table 5: g_o > 0 => B = 0
      for (int e = 0; e < element_count(p); ++e)
        {
          double *el = elem(st, e);
          element_geometry(p, st[h_R], e, el[e_area], el[e_rs], el[e_rt]);
          el[e_B]   = bond_all ? 3 : 0;
          el[e_gap] = interface_gap(st, el[e_rs], el[e_rt]);
        }
    }

    static void update(const Params &p, const ContactStep<dim> &k, double *st,
                       ContactForce &f, EventSink &events)
    {
      // Tracked interface motion (memo Eq. 15 / 22). In 2D only d_st and d_bs
      // exist.
      const double d_ss = dim == 3 ? k.d_ss : 0.0;
      const double d_tw = dim == 3 ? k.d_twist : 0.0;
      st[h_gs] += k.d_n;
      st[h_dss] += d_ss;
      st[h_dst] += k.d_st;
      st[h_tbs] += k.d_bs;
      if (dim == 3)
        st[h_tbt] += k.d_bt;

      const double tan_phi = std::tan(p.fa * M_PI / 180.0);
      f                    = ContactForce{};
      double mz            = 0; // 2D resultant moment about +z
      for (int e = 0; e < element_count(p); ++e)
        {
          double      *el = elem(st, e);
          const double A = el[e_area], rs = el[e_rs], rt = el[e_rt];
          const double g0     = el[e_gap];
          const double g1     = interface_gap(st, rs, rt);
          bool         bonded = el[e_B] == 3;
          bool         slip   = false;

          auto break_event = [&](int mode, double strength) {
            LawEvent ev;
            ev.kind     = LawEvent::bond_break;
            ev.element  = e;
            ev.mode     = mode;
            ev.r_s      = rs;
            ev.r_t      = rt;
            ev.size     = element_size(p, st, el);
            ev.gap      = g1;
            ev.strength = strength;
            events.push(ev);
          };

          // Step 1: normal force (Eq. 32) and tension check.
          double Fn, Mb;
          normal_and_bending(p, st, el, bonded, Fn, Mb);
          double sigma = Fn / A;
          double Fss = el[e_fss], Fst = el[e_fst];
          bool   do_shear = true;
          if (bonded && sigma > p.ten)
            {
              el[e_B] = 1;
              bonded  = false;
              Fn = Fss = Fst = 0;
              do_shear       = false;
              break_event(0, p.ten);
            }
          else if (!bonded && sigma >= 0)
            {
              Fss = Fst = 0;
              do_shear  = false;
            }

          // Step 2: shear (Eq. 33-34) with the effective increment at the
          // centroid, including twist (Eq. 12: n x r = r_s t - r_t s).
          if (do_shear)
            {
              const double alpha = (!bonded && g0 > 0 && g1 < 0) ? g1 / (g1 - g0) : 1.0;
              const double ds    = alpha * (d_ss - d_tw * rt);
              const double dtt   = alpha * (k.d_st + d_tw * rs);
              Fss -= p.ks * A * ds;
              Fst -= p.ks * A * dtt;
              const double tau = std::sqrt(Fss * Fss + Fst * Fst) / A;
              if (!bonded)
                {
                  const double tau_c = -p.fric * sigma;
                  if (tau > tau_c)
                    {
                      const double scale = tau_c / tau; // tau > tau_c >= 0
                      Fss *= scale;
                      Fst *= scale;
                      slip = true;
                      // memo Eq. 39
                      el[e_eslip] += tau_c * A * std::sqrt(ds * ds + dtt * dtt);
                    }
                }
              else
                {
                  const double tau_c = p.coh - sigma * tan_phi;
                  if (tau > tau_c)
                    {
                      el[e_B] = 2;
                      bonded  = false;
                      Fss = Fst = 0;
                      // re-evaluate Fn as in step 1, now unbonded
                      normal_and_bending(p, st, el, false, Fn, Mb);
                      break_event(1, tau_c);
                    }
                }
            }
          if (slip != (el[e_slip] != 0))
            {
              LawEvent ev;
              ev.kind    = slip ? LawEvent::slip_start : LawEvent::slip_end;
              ev.element = e;
              ev.mode    = slip ? 0 : 1; // memo Table 7 slip-change mode
              ev.r_s     = rs;
              ev.r_t     = rt;
              ev.size    = element_size(p, st, el);
              ev.gap     = g1;
              events.push(ev);
              el[e_slip] = slip ? 1 : 0;
            }

          // Step 3: bending moment (Eq. 35) with the final bond state; after
          // a tension break the memo zeroes Fn for this step and Mb follows
          // the unbonded stress field.
          {
            double fn_dummy;
            normal_and_bending(p, st, el, el[e_B] == 3, fn_dummy, Mb);
          }

          el[e_fn]  = Fn;
          el[e_fss] = Fss;
          el[e_fst] = Fst;
          el[e_mb]  = Mb;
          el[e_gap] = g1;

          // Resultant (memo Eq. 23-24), r = rs s + rt t, force -Fn n + Fs.
          f.Fn += Fn;
          f.Fss += Fss;
          f.Fst += Fst;
          f.Mt += rs * Fst - rt * Fss;
          if (dim == 2)
            mz += rt * Fn + Mb;
          else
            {
              f.Mbs += -Fn * rt;
              f.Mbt += Fn * rs;
            }
        }
      if (dim == 2)
        {
          f.Fss = f.Mt = f.Mbt = 0;
          f.Mbs                = -mz; // s = -k
        }
    }

    /// Memo §1.6: active if any element is bonded or has a negative gap
    /// (2D: anywhere over the element, as the stress field of Eq. 28).
    static bool active(const Params &p, const double *st, double /*gap*/)
    {
      for (int e = 0; e < element_count(p); ++e)
        {
          const double *el = elem(st, e);
          if (el[e_B] == 3)
            return true;
          if (dim == 2)
            {
              const double rbar = st[h_R] / p.Nr;
              if (interface_gap(st, 0, el[e_rt] + rbar) < 0 ||
                  interface_gap(st, 0, el[e_rt] - rbar) < 0)
                return true;
            }
          else if (interface_gap(st, el[e_rs], el[e_rt]) < 0)
            return true;
        }
      return false;
    }

    /// Memo §1.6: no bond left and the notional-surface centres further apart
    /// than the flat-joint diameter.
    static bool deletable(const Params &p, const double *st, double /*gap*/)
    {
      if (bonded_count(p, st) > 0)
        return false;
      const double d =
          std::sqrt(st[h_gs] * st[h_gs] + st[h_dss] * st[h_dss] + st[h_dst] * st[h_dst]);
      return d > 2 * st[h_R];
    }

    /// Memo Eq. 41-42 for the whole cross section.
    static ContactStiffness stiffness(const Params &p, const ContactGeometry<dim> &g,
                                      const double *st)
    {
      const double R = st ? st[h_R] : p.rmul * g.min_radius();
      const double A = dim == 2 ? 2 * R : M_PI * R * R;
      const double I = dim == 2 ? 2.0 / 3.0 * R * R * R : 0.25 * M_PI * R * R * R * R;
      const double J = dim == 2 ? 0.0 : 0.5 * M_PI * R * R * R * R;
      return {p.kn * A, p.ks * A, p.kn * I, p.ks * J};
    }

    /// Memo Eq. 36-37 (element twisting moment is zero, memo footnote 5).
    static double strain_energy(const Params &p, const double *st)
    {
      double E = 0;
      for (int e = 0; e < element_count(p); ++e)
        {
          const double *el = elem(st, e);
          const double  A  = el[e_area];
          double        I;
          if (dim == 2)
            {
              const double rbar = st[h_R] / p.Nr;
              I                 = 2.0 / 3.0 * rbar * rbar * rbar;
            }
          else
            {
              const double re2 = A / M_PI;
              I                = 0.25 * M_PI * re2 * re2;
            }
          if (p.kn > 0)
            E += 0.5 *
                 (el[e_fn] * el[e_fn] / (p.kn * A) + el[e_mb] * el[e_mb] / (p.kn * I));
          if (p.ks > 0)
            E += 0.5 * (el[e_fss] * el[e_fss] + el[e_fst] * el[e_fst]) / (p.ks * A);
        }
      return E;
    }

    /// Memo Eq. 38.
    static double slip_energy(const Params &p, const double *st)
    {
      double E = 0;
      for (int e = 0; e < element_count(p); ++e)
        E += elem(st, e)[e_eslip];
      return E;
    }

    // ---- per-contact setters for material genesis (memo §1.10) -----------
    /// Sets g_o and g_s (memo Eq. 31); g0 > 0 unbonds every element (Table 5).
    static void set_initial_gap(const Params &p, double *st, double g0)
    {
      st[h_gs] = g0;
      for (int e = 0; e < element_count(p); ++e)
        {
          double *el = elem(st, e);
          el[e_gap]  = interface_gap(st, el[e_rs], el[e_rt]);
          if (g0 > 0)
            el[e_B] = 0;
        }
    }

    /// Bond element e (0-based) or all (e < 0). Memo §1.10: only elements
    /// with a zero gap over their entire surface can be bonded (tolerance
    /// 1e-12 R for round-off). Forces are left for the next update. Returns
    /// the number of elements bonded by this call.
    static int bond(const Params &p, double *st, int element = -1)
    {
      int          n   = 0;
      const double tol = 1e-12 * st[h_R];
      for (int e = 0; e < element_count(p); ++e)
        {
          if (element >= 0 && e != element)
            continue;
          double *el = elem(st, e);
          bool    zero;
          if (dim == 2)
            {
              const double rbar = st[h_R] / p.Nr;
              zero = std::abs(interface_gap(st, 0, el[e_rt] + rbar)) <= tol &&
                     std::abs(interface_gap(st, 0, el[e_rt] - rbar)) <= tol;
            }
          else // the gap is planar: zero everywhere iff g_s = 0 and theta_b = 0
            zero =
                std::abs(st[h_gs]) <= tol &&
                std::sqrt(st[h_tbs] * st[h_tbs] + st[h_tbt] * st[h_tbt]) * st[h_R] <= tol;
          if (zero && el[e_B] != 3)
            {
              el[e_B] = 3;
              ++n;
            }
        }
      return n;
    }

    /// Unbond element e (0-based) or all (e < 0): B = 0 (memo §1.10).
    static void unbond(const Params &p, double *st, int element = -1)
    {
      for (int e = 0; e < element_count(p); ++e)
        if (element < 0 || e == element)
          elem(st, e)[e_B] = 0;
    }

    // ---- getters -------------------------------------------------------------
    static int bond_state(const Params &, const double *st, int e)
    {
      return int(elem(st, e)[e_B]);
    }
    static bool slipping(const Params &, const double *st, int e)
    {
      return elem(st, e)[e_slip] != 0;
    }
    static double element_area(const Params &, const double *st, int e)
    {
      return elem(st, e)[e_area];
    }
    static std::array<double, 2> element_centroid(const Params &, const double *st, int e)
    {
      return {elem(st, e)[e_rs], elem(st, e)[e_rt]};
    }
    /// Gap at the element centroid g^(e) (memo Eq. 21).
    static double element_gap(const Params &, const double *st, int e)
    {
      return interface_gap(st, elem(st, e)[e_rs], elem(st, e)[e_rt]);
    }
    /// Element force {Fn, Fss, Fst} and bending moment (2D: about +z).
    static std::array<double, 4> element_force(const Params &, const double *st, int e)
    {
      const double *el = elem(st, e);
      return {el[e_fn], el[e_fss], el[e_fst], el[e_mb]};
    }
    static double element_slip_energy(const Params &, const double *st, int e)
    {
      return elem(st, e)[e_eslip];
    }
    static double                surface_gap(const double *st) { return st[h_gs]; }
    static double                radius(const double *st) { return st[h_R]; }
    static std::array<double, 2> relative_bend(const double *st)
    {
      return {st[h_tbs], st[h_tbt]};
    }
    static int bonded_count(const Params &p, const double *st)
    {
      int n = 0;
      for (int e = 0; e < element_count(p); ++e)
        n += elem(st, e)[e_B] == 3;
      return n;
    }
  };
} // namespace demfem::dem
