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
// Conventions (see dem/engine/contact_law.h): everything is in contact-plane
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
#include "dem/engine/contact_law.h"
#include "dem/laws/flat_joint_elements.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace demfem::dem
{
  template <int dim>
  struct FlatJointLaw
  {
    static constexpr const char *name = "flatjoint";

    static constexpr BondType bond_type = BondType::flat_joint;

    /// Per-contact properties (memo Table 5; names of the memo keywords
    /// without the "fj_" prefix).
    struct Props
    {
      double rmul   = 1.0; ///< radius multiplier lambda (memo Eq. 30)
      double gap0   = 0.0; ///< initial surface gap g_o
      double kn     = 0.0; ///< normal stiffness [stress/disp]
      double ks     = 0.0; ///< shear stiffness [stress/disp]
      double fric   = 0.0; ///< friction coefficient mu
      double ten    = 0.0; ///< tensile strength sigma_c [stress]
      double coh    = 0.0; ///< cohesion c [stress]
      double fa     = 0.0; ///< friction angle phi [degrees]
      double tan_fa = 0.0; ///< tan(phi), derived
      /// Initial microstructural type T (memo Table 4): 1 bonded, 2 gapped,
      /// 3 slit, 4 other; 0 until the contact is installed.
      double mtype = 0;
    };

    /// Group-wide: the element grid and the install flag.
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
      int  Nr     = 2;     ///< elements in radial direction (2D: elements)
      int  Nal    = 4;     ///< elements in circumferential direction (3D only)
      bool bonded = false; ///< install with all elements bonded (if gap0 = 0)
      /// 3D unit-radius element geometry of (Nr, Nal), set by prepare().
      const double *unit_table = nullptr;

      void validate(const std::string &where) const
      {
        const double inf = HUGE_VAL;
        check_range(where, "Nr", Nr, 1, inf);
        if (dim == 3)
          check_range(where, "Nal", Nal, 3, inf);
        check_range(where, "rmul", this->rmul, 0, inf, true, false);
        check_range(where, "gap0", this->gap0, 0, inf);
        check_range(where, "kn", this->kn, 0, inf);
        check_range(where, "ks", this->ks, 0, inf);
        check_range(where, "fric", this->fric, 0, inf);
        check_range(where, "ten", this->ten, 0, inf);
        check_range(where, "coh", this->coh, 0, inf);
        check_range(where, "fa", this->fa, 0, 90, false, true);
      }
    };

    /// The group's constants: the 3D element table of (Nr, Nal).
    static void prepare(Params &p)
    {
      p.unit_table = dim == 3 ? flat_joint_unit_geometry(p.Nr, p.Nal) : nullptr;
      derive(p, p);
    }
    /// The block with its bond strengths infinite: what the contact loop
    /// hands to `update` while bond breakage is suspended
    /// (Model::suspend_bond_breakage, docs/architecture.md).
    static Props unbreakable(Props q)
    {
      q.ten = q.coh = HUGE_VAL;
      return q;
    }
    /// tan(phi), and the initial microstructural type from the install flag
    /// and g_o (memo Table 4) unless genesis designated it.
    static void derive(const Params &p, Props &q)
    {
      q.tan_fa = std::tan(q.fa * M_PI / 180.0);
      if (q.mtype == 0)
        q.mtype = (p.bonded && q.gap0 == 0) ? 1 : q.gap0 > 0 ? 2 : 3;
    }

    /// Memo Table 5: kn, ks, fric, ten, coh, fa modifiable; rmul, gap0 set
    /// before cycling; mtype read only.
    static const std::vector<PropertyField<Props>> &properties()
    {
      using P                                            = Props;
      const double                                   inf = HUGE_VAL;
      static const std::vector<PropertyField<Props>> f   = {
            {"fj_kn", [](const P &q) { return q.kn; }, [](P &q, double v) { q.kn = v; },
             true, 0, inf},
            {"fj_ks", [](const P &q) { return q.ks; }, [](P &q, double v) { q.ks = v; },
             true, 0, inf},
            {"fj_fric", [](const P &q) { return q.fric; },
             [](P &q, double v) { q.fric = v; }, true, 0, inf},
            {"fj_ten", [](const P &q) { return q.ten; }, [](P &q, double v) { q.ten = v; },
             true, 0, inf},
            {"fj_coh", [](const P &q) { return q.coh; }, [](P &q, double v) { q.coh = v; },
             true, 0, inf},
            {"fj_fa", [](const P &q) { return q.fa; }, [](P &q, double v) { q.fa = v; },
             true, 0, 89.999999},
            {"fj_rmul", [](const P &q) { return q.rmul; },
             [](P &q, double v) { q.rmul = v; }, false, 0, inf},
            {"fj_gap0", [](const P &q) { return q.gap0; },
             [](P &q, double v) { q.gap0 = v; }, false, 0, inf},
            {"fj_mtype", [](const P &q) { return q.mtype; },
             [](P &q, double v) { q.mtype = v; }, false, 0, 4}};
      return f;
    }

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
    // Per contact: a header R, g_s, delta_ss, delta_st, theta_bs, theta_bt
    // (memo Eq. 15/22), then the bond state and slip flag of each element in
    // one byte (B + 4 slip; ceil(ne / 8) doubles hold them, and bytes 0-7
    // always form a finite double, so the block copies and checkpoints as
    // doubles), then one array of doubles over the elements per field: the
    // shear forces, the slip energy and (2D only) the normal force and
    // bending moment. The update is memory-bound, so nothing derivable is stored:
    // the element geometry depends only on (Nr, Nal, e) scaled by R (memo
    // Eq. 13, 16-17: A = R^2 A^, r = R r^); the centroid gap at the end of
    // the previous step (g_0 of Eq. 33) is the gap of the header before this
    // step's increments; the 3D element bending moment is zero (Eq. 50) and
    // the 3D element normal force is a function of the current gap and bond
    // state (Eq. 32, 50; a tension break leaves g > 0 and B = 1, for which
    // it gives the memo's Fn = 0). Arrays per field (rather than per element)
    // keep the rarely changing bond codes and slip energies in cache lines
    // that the update only reads, so they are not written back to memory.
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
    enum : int
    {
      f_fss,
      f_fst,
      f_eslip,
      f_fn, ///< 2D only
      f_mb  ///< 2D only
    };
    static constexpr int n_field = dim == 2 ? 5 : 3;

    static int element_count(const Params &p) { return dim == 2 ? p.Nr : p.Nr * p.Nal; }
    /// Doubles holding the element codes (one byte each).
    static int code_words(const Params &p) { return (element_count(p) + 7) / 8; }
    static int state_size(const Params &p)
    {
      return n_head + code_words(p) + n_field * element_count(p);
    }

    /// Array of field f over the elements.
    static double *field(const Params &p, double *st, int f)
    {
      return st + n_head + code_words(p) + f * element_count(p);
    }
    static const double *field(const Params &p, const double *st, int f)
    {
      return st + n_head + code_words(p) + f * element_count(p);
    }
    /// Element codes B + 4 slip (B: 0 unbonded, 1/2 broke in tension/shear,
    /// 3 bonded), one byte per element (byte access to the doubles' storage).
    static unsigned char *code_array(double *st)
    {
      return reinterpret_cast<unsigned char *>(st + n_head);
    }
    static const unsigned char *code_array(const double *st)
    {
      return reinterpret_cast<const unsigned char *>(st + n_head);
    }

    static int           code_bond(unsigned char c) { return c & 3; }
    static bool          code_slip(unsigned char c) { return c >= 4; }
    static unsigned char make_code(int B, bool slip) { return B + (slip ? 4 : 0); }

    /// 3D unit-radius element table (dem/laws/flat_joint_elements.h): a group
    /// looks it up once (prepare), Params made by hand here.
    static const double *unit_geometry(const Params &p)
    {
      return p.unit_table ? p.unit_table : flat_joint_unit_geometry(p.Nr, p.Nal);
    }

    /// Element geometry for radius R with the unit table ug (3D, from
    /// unit_geometry; unused in 2D).
    static void scaled_geometry(const Params &p, double R, const double *ug, int e,
                                double &A, double &rs, double &rt)
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
          const int ne = p.Nr * p.Nal;
          A            = R * R * ug[e];
          rs           = R * ug[ne + e];
          rt           = R * ug[2 * ne + e];
        }
    }

    /// 3D element normal force (memo Eq. 32, 50) for bond state B.
    static double normal_force_3d(const Props &q, const double *st, double A, double rs,
                                  double rt, int B)
    {
      const double g = interface_gap(st, rs, rt);
      return (B != 3 && g >= 0) ? 0.0 : q.kn * g * A;
    }

    /// Element area and centroid (r_s, r_t) for radius R: memo Eq. 13 (2D),
    /// Eq. 16-17 (3D); e is 0-based.
    static void element_geometry(const Params &p, double R, int e, double &A, double &rs,
                                 double &rt)
    {
      scaled_geometry(p, R, dim == 3 ? unit_geometry(p) : nullptr, e, A, rs, rt);
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

    /// Element normal force and bending moment for an element centred at rho
    /// (2D, exact, Eq. 44-49) or at (rs, rt) with area A (3D, Eq. 50: Mb = 0).
    static void normal_and_bending(const Params &p, const Props &q, const double *st,
                                   double A, double rs, double rt, bool bonded,
                                   double &Fn, double &Mb)
    {
      if (dim == 2)
        {
          const double rbar = st[h_R] / p.Nr;
          // end a = larger rho (see the header comment)
          const double ga = interface_gap(st, 0, rt + rbar);
          const double gb = interface_gap(st, 0, rt - rbar);
          integrate_2d(q.kn, rbar, ga, gb, bonded, Fn, Mb);
        }
      else
        {
          const double g = interface_gap(st, rs, rt);
          Fn             = (!bonded && g >= 0) ? 0.0 : q.kn * g * A;
          Mb             = 0.0;
        }
    }

    /// Crack size (fistPkg §3.4, memo footnote 3): 2D element length,
    /// 3D twice the radius of the disk of equal area.
    static double element_size(const Params &p, const double *st, double A)
    {
      return dim == 2 ? 2 * st[h_R] / p.Nr : 2 * std::sqrt(A / M_PI);
    }

    // ---- contract -----------------------------------------------------------
    static void install(const Params &p, const Props &q, const ContactGeometry<dim> &g,
                        double *st)
    {
      for (int i = 0, n = state_size(p); i < n; ++i)
        st[i] = 0;                                   // memo Eq. 29, 31
      st[h_R]             = q.rmul * g.min_radius(); // memo Eq. 30
      st[h_gs]            = q.gap0;                  // memo Eq. 31
      const bool bond_all = p.bonded && q.gap0 == 0; // Table 5: g_o > 0 => B = 0
      for (int e = 0; e < element_count(p); ++e)
        code_array(st)[e] = make_code(bond_all ? 3 : 0, false);
    }

    static void update(const Params &p, const Props &q, const ContactStep<dim> &k,
                       double *st, ContactForce &f, EventSink &events)
    {
      // Gap field at the end of the previous step (g_0 of memo Eq. 33).
      const double gs0 = st[h_gs], tbs0 = st[h_tbs], tbt0 = dim == 3 ? st[h_tbt] : 0.0;
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

      prefetch_next_state(st, state_size(p));

      // Intact 3D material: the branch-free element loop, bitwise the same.
      if constexpr (dim == 3)
        if (update_bonded_elements_3d({element_count(p), code_array(st), unit_geometry(p),
                                       field(p, st, f_fss), field(p, st, f_fst), st[h_R],
                                       st[h_gs], st[h_tbs], st[h_tbt], q.kn, q.ks, q.ten,
                                       q.coh, q.tan_fa},
                                      k.d_ss, k.d_st, k.d_twist, f))
          return;

      // Per-contact invariants hoisted out of the element loop.
      const double   R   = st[h_R];
      const double   gs1 = st[h_gs], tbs1 = st[h_tbs], tbt1 = dim == 3 ? st[h_tbt] : 0.0;
      const double  *ug      = dim == 3 ? unit_geometry(p) : nullptr;
      const double   tan_phi = q.tan_fa;
      const int      ne      = element_count(p);
      unsigned char *codes   = code_array(st);
      double        *fss_a   = field(p, st, f_fss);
      double        *fst_a   = field(p, st, f_fst);
      double        *eslip_a = field(p, st, f_eslip);

      // 3D: the resultant is summed in two partial sums, even and odd
      // elements, as the two lanes of the fast path (update_bonded_elements_3d), so
      // both give the same bits.
      ContactForce part[2];
      double       mz = 0; // 2D resultant moment about +z
      for (int e = 0; e < ne; ++e)
        {
          double A, rs, rt;
          scaled_geometry(p, R, ug, e, A, rs, rt);
          const double        g0       = gs0 + rt * tbs0 - rs * tbt0;
          const double        g1       = gs1 + rt * tbs1 - rs * tbt1;
          const unsigned char code     = codes[e];
          int                 B        = code_bond(code);
          const bool          was_slip = code_slip(code);
          bool                bonded   = B == 3;
          bool                slip     = false;

          auto break_event = [&](int mode, double strength) {
            LawEvent ev;
            ev.kind     = LawEvent::bond_break;
            ev.element  = e;
            ev.mode     = mode;
            ev.r_s      = rs;
            ev.r_t      = rt;
            ev.size     = element_size(p, st, A);
            ev.gap      = g1;
            ev.strength = strength;
            events.push(ev);
          };

          // Step 1: normal force (Eq. 32) and tension check (sigma = Fn/A
          // compared as forces, A > 0).
          double Fn, Mb = 0;
          if (dim == 3)
            Fn = (!bonded && g1 >= 0) ? 0.0 : q.kn * g1 * A; // normal_force_3d
          else
            normal_and_bending(p, q, st, A, rs, rt, bonded, Fn, Mb);
          double Fss = fss_a[e], Fst = fst_a[e];
          bool   do_shear = true, tension_break = false;
          if (bonded && Fn > q.ten * A)
            {
              B      = 1;
              bonded = false;
              Fn = Fss = Fst = 0;
              do_shear       = false;
              tension_break  = true;
              break_event(0, q.ten);
            }
          else if (!bonded && Fn >= 0)
            {
              Fss = Fst = 0;
              do_shear  = false;
            }

          // Step 2: shear (Eq. 33-34) with the effective increment at the
          // centroid, including twist (Eq. 12: n x r = r_s t - r_t s). The
          // strength tests compare squared forces, so the square root is only
          // taken when the element slips.
          if (do_shear)
            {
              const double alpha = (!bonded && g0 > 0 && g1 < 0) ? g1 / (g1 - g0) : 1.0;
              const double ds    = alpha * (d_ss - d_tw * rt);
              const double dtt   = alpha * (k.d_st + d_tw * rs);
              const double ksA   = q.ks * A;
              Fss -= ksA * ds;
              Fst -= ksA * dtt;
              const double F2 = Fss * Fss + Fst * Fst;
              if (!bonded)
                {
                  const double Tc = -q.fric * Fn; // >= 0: Fn < 0 here
                  if (F2 > Tc * Tc)
                    {
                      const double scale = Tc / std::sqrt(F2);
                      Fss *= scale;
                      Fst *= scale;
                      slip = true;
                      // memo Eq. 39
                      eslip_a[e] += Tc * std::sqrt(ds * ds + dtt * dtt);
                    }
                }
              else
                {
                  const double Tc = q.coh * A - Fn * tan_phi; // tau_c A
                  if (Tc < 0 || F2 > Tc * Tc)
                    {
                      B      = 2;
                      bonded = false;
                      Fss = Fst = 0;
                      // re-evaluate Fn as in step 1, now unbonded
                      if (dim == 3)
                        Fn = g1 >= 0 ? 0.0 : q.kn * g1 * A;
                      else
                        normal_and_bending(p, q, st, A, rs, rt, false, Fn, Mb);
                      break_event(1, Tc / A);
                    }
                }
            }
          if (slip != was_slip)
            {
              LawEvent ev;
              ev.kind    = slip ? LawEvent::slip_start : LawEvent::slip_end;
              ev.element = e;
              ev.mode    = slip ? 0 : 1; // memo Table 7 slip-change mode
              ev.r_s     = rs;
              ev.r_t     = rt;
              ev.size    = element_size(p, st, A);
              ev.gap     = g1;
              events.push(ev);
            }

          // Step 3: bending moment (Eq. 35) with the final bond state; after
          // a tension break the memo zeroes Fn for this step and Mb follows
          // the unbonded stress field. Otherwise Mb from steps 1-2 already
          // belongs to the final bond state. 3D: Mb = 0 (Eq. 50).
          if (dim == 2 && tension_break)
            {
              double fn_dummy;
              normal_and_bending(p, q, st, A, rs, rt, false, fn_dummy, Mb);
            }

          const unsigned char new_code = make_code(B, slip);
          if (new_code != code) // keep the cache line clean
            codes[e] = new_code;
          fss_a[e] = Fss;
          fst_a[e] = Fst;
          if (dim == 2)
            {
              field(p, st, f_fn)[e] = Fn;
              field(p, st, f_mb)[e] = Mb;
            }

          // Resultant (memo Eq. 23-24), r = rs s + rt t, force -Fn n + Fs.
          ContactForce &sum = part[dim == 3 ? e & 1 : 0];
          sum.Fn += Fn;
          sum.Fss += Fss;
          sum.Fst += Fst;
          sum.Mt += rs * Fst - rt * Fss;
          if (dim == 2)
            mz += rt * Fn + Mb;
          else
            {
              sum.Mbs += -Fn * rt;
              sum.Mbt += Fn * rs;
            }
        }
      f = part[0];
      if (dim == 3)
        f = ContactForce{part[0].Fn + part[1].Fn,   part[0].Fss + part[1].Fss,
                         part[0].Fst + part[1].Fst, part[0].Mt + part[1].Mt,
                         part[0].Mbs + part[1].Mbs, part[0].Mbt + part[1].Mbt};
      if (dim == 2)
        {
          f.Fss = f.Mt = f.Mbt = 0;
          f.Mbs                = -mz; // s = -k
        }
    }

    /// Memo §1.6: active if any element is bonded or has a negative gap
    /// (2D: anywhere over the element, as the stress field of Eq. 28).
    static bool active(const Params &p, const Props &, const double *st, double /*gap*/)
    {
      for (int e = 0; e < element_count(p); ++e)
        {
          if (bond_state(p, st, e) == 3)
            return true;
          double A, rs, rt;
          element_geometry(p, st[h_R], e, A, rs, rt);
          if (dim == 2)
            {
              const double rbar = st[h_R] / p.Nr;
              if (interface_gap(st, 0, rt + rbar) < 0 ||
                  interface_gap(st, 0, rt - rbar) < 0)
                return true;
            }
          else if (interface_gap(st, rs, rt) < 0)
            return true;
        }
      return false;
    }

    /// Memo §1.6: no bond left and the notional-surface centres further apart
    /// than the flat-joint diameter.
    static bool deletable(const Params &p, const Props &, const double *st,
                          double /*gap*/)
    {
      if (bonded_count(p, st) > 0)
        return false;
      const double d =
          std::sqrt(st[h_gs] * st[h_gs] + st[h_dss] * st[h_dss] + st[h_dst] * st[h_dst]);
      return d > 2 * st[h_R];
    }

    /// Memo Eq. 41-42 for the whole cross section.
    static ContactStiffness stiffness(const Params &, const Props &q,
                                      const ContactGeometry<dim> &g, const double *st)
    {
      const double R = st ? st[h_R] : q.rmul * g.min_radius();
      const double A = dim == 2 ? 2 * R : M_PI * R * R;
      const double I = dim == 2 ? 2.0 / 3.0 * R * R * R : 0.25 * M_PI * R * R * R * R;
      const double J = dim == 2 ? 0.0 : 0.5 * M_PI * R * R * R * R;
      return {q.kn * A, q.ks * A, q.kn * I, q.ks * J};
    }

    /// Memo Eq. 36-37 (element twisting moment is zero, memo footnote 5;
    /// 3D bending moment zero, Eq. 50).
    static double strain_energy(const Params &p, const Props &q, const double *st)
    {
      if constexpr (dim == 3)
        return strain_energy_3d(p, q, st);
      const double        *ug   = dim == 3 ? unit_geometry(p) : nullptr;
      const double         R    = st[h_R];
      const double         rbar = R / p.Nr;
      const double         I2d  = 2.0 / 3.0 * rbar * rbar * rbar;
      const unsigned char *code = code_array(st);
      const double        *fss = field(p, st, f_fss), *fst = field(p, st, f_fst);
      double               E = 0;
      for (int e = 0; e < element_count(p); ++e)
        {
          double A, rs, rt;
          scaled_geometry(p, R, ug, e, A, rs, rt);
          if (q.kn > 0)
            {
              const double Fn =
                  dim == 2 ? field(p, st, f_fn)[e]
                           : normal_force_3d(q, st, A, rs, rt, code_bond(code[e]));
              E += 0.5 * Fn * Fn / (q.kn * A);
              if (dim == 2)
                {
                  const double Mb = field(p, st, f_mb)[e];
                  E += 0.5 * Mb * Mb / (q.kn * I2d);
                }
            }
          if (q.ks > 0)
            E += 0.5 * (fss[e] * fss[e] + fst[e] * fst[e]) / (q.ks * A);
        }
      return E;
    }

    /// 3D strain energy without a division per element: the normal part
    /// Fn^2 / (2 kn A) is kn g^2 A / 2 where the element carries Fn = kn g A
    /// (Eq. 32, 50) and 0 where it does not; the shear part uses the unit
    /// table's 1/A^ (evaluated on the energy-check steps inside the force
    /// pass, so its cost counts).
    static double strain_energy_3d(const Params &p, const Props &q, const double *st)
    {
      const int     ne = element_count(p);
      const double *ug = unit_geometry(p);
      const double *uA = ug, *urs = ug + ne, *urt = ug + 2 * ne, *uinvA = ug + 3 * ne;
      const double  R = st[h_R], gs = st[h_gs], tbs = st[h_tbs], tbt = st[h_tbt];
      const unsigned char *code = code_array(st);
      const double        *fss = field(p, st, f_fss), *fst = field(p, st, f_fst);
      const double         half_kn_R2 = 0.5 * q.kn * R * R;
      const double         half_R2_ks = q.ks > 0 ? 0.5 / (q.ks * R * R) : 0.0;
      double               E          = 0;
      for (int e = 0; e < ne; ++e)
        {
          const double g       = gs + R * urt[e] * tbs - R * urs[e] * tbt;
          const bool   carries = code_bond(code[e]) == 3 || g < 0;
          E += (carries ? half_kn_R2 * g * g * uA[e] : 0.0) +
               half_R2_ks * (fss[e] * fss[e] + fst[e] * fst[e]) * uinvA[e];
        }
      return E;
    }

    /// Memo Eq. 38.
    static double slip_energy(const Params &p, const Props &, const double *st)
    {
      double E = 0;
      for (int e = 0; e < element_count(p); ++e)
        E += field(p, st, f_eslip)[e];
      return E;
    }

    // ---- per-contact setters for material genesis (memo §1.10) -----------
    /// Sets g_o and g_s (memo Eq. 31); g0 > 0 unbonds every element (Table 5).
    /// The previous-step gap of Eq. 33 follows from the header.
    static void set_initial_gap(const Params &p, double *st, double g0)
    {
      st[h_gs] = g0;
      if (g0 > 0)
        unbond(p, st);
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
          unsigned char *code = code_array(st) + e;
          bool           zero;
          if (dim == 2)
            {
              const double rbar = st[h_R] / p.Nr;
              const double rho  = element_centroid(p, st, e)[1];
              zero              = std::abs(interface_gap(st, 0, rho + rbar)) <= tol &&
                     std::abs(interface_gap(st, 0, rho - rbar)) <= tol;
            }
          else // the gap is planar: zero everywhere iff g_s = 0 and theta_b = 0
            zero =
                std::abs(st[h_gs]) <= tol &&
                std::sqrt(st[h_tbs] * st[h_tbs] + st[h_tbt] * st[h_tbt]) * st[h_R] <= tol;
          if (zero && code_bond(*code) != 3)
            {
              *code = make_code(3, code_slip(*code));
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
          {
            unsigned char *code = code_array(st) + e;
            *code               = make_code(0, code_slip(*code));
          }
    }

    // ---- getters -------------------------------------------------------------
    static int bond_state(const Params &, const double *st, int e)
    {
      return code_bond(code_array(st)[e]);
    }
    static bool slipping(const Params &p, const double *st, int e)
    {
      return code_slip(code_array(st)[e]);
    }
    static double element_area(const Params &p, const double *st, int e)
    {
      double A, rs, rt;
      element_geometry(p, st[h_R], e, A, rs, rt);
      return A;
    }
    static std::array<double, 2> element_centroid(const Params &p, const double *st,
                                                  int e)
    {
      double A, rs, rt;
      element_geometry(p, st[h_R], e, A, rs, rt);
      return {{rs, rt}};
    }
    /// Gap at the element centroid g^(e) (memo Eq. 21).
    static double element_gap(const Params &p, const double *st, int e)
    {
      const auto r = element_centroid(p, st, e);
      return interface_gap(st, r[0], r[1]);
    }
    /// Element force {Fn, Fss, Fst} and bending moment (2D: about +z; 3D: 0,
    /// memo Eq. 50) of the last update. 3D Fn is evaluated from the gap and
    /// bond state exactly as the update does (see the state layout).
    static std::array<double, 4> element_force(const Params &p, const Props &q,
                                               const double *st, int e)
    {
      const double Fss = field(p, st, f_fss)[e], Fst = field(p, st, f_fst)[e];
      if (dim == 2)
        return {field(p, st, f_fn)[e], Fss, Fst, field(p, st, f_mb)[e]};
      double A, rs, rt;
      element_geometry(p, st[h_R], e, A, rs, rt);
      return {normal_force_3d(q, st, A, rs, rt, bond_state(p, st, e)), Fss, Fst, 0.0};
    }
    static double element_slip_energy(const Params &p, const double *st, int e)
    {
      return field(p, st, f_eslip)[e];
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
        n += bond_state(p, st, e) == 3;
      return n;
    }
  };
} // namespace demfem::dem
