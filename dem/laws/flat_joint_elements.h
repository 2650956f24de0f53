#pragma once
// Flat-joint element arithmetic shared by FlatJointLaw (dem/laws/flat_joint_law.h):
// the 3D unit-radius element geometry table and the branch-free fast path of
// the element loop for intact material. Kept apart from the law so that the
// physics reads without the SIMD and table-caching details.
#include "dem/engine/contact_law.h"

#include <cstdint>
#include <cstring>

namespace demfem::dem
{
  /// 3D unit-radius element geometry of an Nr x Nal flat joint (memo Eq.
  /// 16-17 with R = 1): four arrays over the elements, A^, r^_s, r^_t and
  /// 1/A^ (so that the element loops vectorise and the strain energy needs
  /// no division). One table per (Nr, Nal) for the whole process, built on
  /// first use (under a mutex), never freed, never moved.
  const double *flat_joint_unit_geometry(int Nr, int Nal);

  /// The contact update is bound by memory latency; groups keep the state
  /// blocks of consecutive contacts contiguous, so fetch the next block (of
  /// `n` doubles) while this one is computed. A prefetch never faults,
  /// whatever follows; the address is formed as an integer since it may lie
  /// past the array.
  inline void prefetch_next_state(const double *st, int n)
  {
    const std::size_t    bytes = sizeof(double) * std::size_t(n);
    const std::uintptr_t next  = reinterpret_cast<std::uintptr_t>(st) + bytes;
    for (std::size_t i = 0; i < bytes; i += 64) // one cache line
      __builtin_prefetch(reinterpret_cast<const void *>(next + i), 1);
  }

  /// A 3D flat joint's elements as the fast path reads them: the interface
  /// state after this step's increments and the contact's properties.
  struct BondedElements3d
  {
    int                  ne;              ///< element count Nr x Nal
    const unsigned char *codes;           ///< bond/slip code per element
    const double        *ug;              ///< flat_joint_unit_geometry(Nr, Nal)
    double              *fss, *fst;       ///< element shear forces (updated)
    double               R, gs, tbs, tbt; ///< radius, gap, relative bend (memo Eq. 21)
    double               kn, ks, ten, coh, tan_fa; ///< per-contact properties
  };

  /// Fast path of the 3D element loop for a contact whose elements are all
  /// bonded and not slipping, the state of intact material: the arithmetic
  /// of the general loop for B = 3 (alpha = 1, no slip test, Fn from Eq.
  /// 32/50, shear from Eq. 33-34) without branches, so the element loop
  /// vectorises, then the resultant (Eq. 23-24) summed in element order: the
  /// results are bitwise those of the general loop. Returns false, having
  /// written nothing, if an element is not bonded or would break this step
  /// (the general loop then does the contact, with its events).
  inline bool update_bonded_elements_3d(const BondedElements3d &c, double d_ss_in,
                                        double d_st_in, double d_twist_in,
                                        ContactForce &f)
  {
    // Two elements per instruction (SSE2, part of x86-64; the GCC/Clang
    // vector extension lowers to scalar code elsewhere). Element-wise IEEE
    // arithmetic, so the lanes give exactly the scalar results.
    typedef double v2d __attribute__((vector_size(16)));
    typedef long   v2l __attribute__((vector_size(16)));
    constexpr int  max_elements = 64; // stack arrays below
    const int      ne           = c.ne;
    if (ne > max_elements || ne % 2 != 0)
      return false;
    auto load = [](const double *a) {
      v2d v;
      std::memcpy(&v, a, sizeof v);
      return v;
    };
    auto store = [](double *a, v2d v) { std::memcpy(a, &v, sizeof v); };
    auto splat = [](double x) { return v2d{x, x}; };

    // Every code 3 (bonded, not slipping), eight at a time.
    const unsigned char *codes = c.codes;
    for (int e = 0; e < ne; e += 8)
      {
        const int     n    = ne - e < 8 ? ne - e : 8;
        std::uint64_t word = 0, all3 = 0x0303030303030303ull;
        std::memcpy(&word, codes + e, n);
        if (n < 8)
          all3 &= (1ull << (8 * n)) - 1; // the bytes past ne read as 0
        if (word != all3)
          return false;
      }

    const double *ug = c.ug;
    const double *uA = ug, *urs = ug + ne, *urt = ug + 2 * ne;
    double       *fss_a = c.fss, *fst_a = c.fst;
    const v2d     R = splat(c.R), RR = splat(c.R * c.R);
    const v2d     gs1 = splat(c.gs), tbs1 = splat(c.tbs), tbt1 = splat(c.tbt);
    const v2d     d_ss = splat(d_ss_in), d_st = splat(d_st_in), d_tw = splat(d_twist_in);
    const v2d kn = splat(c.kn), ks = splat(c.ks), ten = splat(c.ten), coh = splat(c.coh);
    const v2d tan_phi = splat(c.tan_fa), zero = splat(0.0);
    double    Fss[max_elements], Fst[max_elements];
    v2l       broken = {0, 0};
    // Resultant (Eq. 23-24): lane 0 sums the even elements, lane 1 the odd
    // ones, as the general loop does.
    v2d sFn = zero, sFss = zero, sFst = zero, sMt = zero, sMbs = zero, sMbt = zero;
    for (int e = 0; e < ne; e += 2)
      {
        const v2d A  = RR * load(uA + e);
        const v2d rs = R * load(urs + e), rt = R * load(urt + e);
        const v2d g1 = gs1 + rt * tbs1 - rs * tbt1;
        const v2d fn = kn * g1 * A;
        const v2d ds = d_ss - d_tw * rt, dtt = d_st + d_tw * rs;
        const v2d ksA = ks * A;
        const v2d fs = load(fss_a + e) - ksA * ds, ft = load(fst_a + e) - ksA * dtt;
        const v2d F2 = fs * fs + ft * ft;
        const v2d Tc = coh * A - fn * tan_phi;
        broken |= (fn > ten * A) | (Tc < zero) | (F2 > Tc * Tc);
        store(Fss + e, fs), store(Fst + e, ft);
        sFn += fn;
        sFss += fs;
        sFst += ft;
        sMt += rs * ft - rt * fs;
        sMbs += -fn * rt;
        sMbt += fn * rs;
      }
    if (broken[0] | broken[1])
      return false;
    std::memcpy(fss_a, Fss, sizeof(double) * ne);
    std::memcpy(fst_a, Fst, sizeof(double) * ne);
    f = ContactForce{sFn[0] + sFn[1], sFss[0] + sFss[1], sFst[0] + sFst[1],
                     sMt[0] + sMt[1], sMbs[0] + sMbs[1], sMbt[0] + sMbt[1]};
    return true;
  }
} // namespace demfem::dem
