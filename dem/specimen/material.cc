// Material parameters (fistPkg Tables 1-5, 7): validation and portable
// random numbers.
#include "dem/specimen/material.h"

#include <cmath>
#include <sstream>

namespace demfem::dem
{
  namespace
  {
    [[noreturn]] void fail(const std::string &where, const std::string &key,
                           const std::string &what)
    {
      throw InputError(where + ": parameter '" + key + "' " + what);
    }

    void check_distribution(const std::string &where, const std::string &key,
                            const Distribution &d)
    {
      const double inf = HUGE_VAL;
      check_range(where, key + "_m", d.mean, 0, inf);
      check_range(where, key + "_sd", d.sd, 0, inf);
      // Below the mean, so that the redrawing ends (at most ~2 draws).
      if (d.min != 0)
        check_range(where, key + "_min", d.min, 0, d.mean, false, true);
    }
  } // namespace

  double MaterialParams::cloud_porosity_or_default(int dim) const
  {
    if (cloud_porosity >= 0)
      return cloud_porosity;
    // fistPkg Table 7: loose (boundary contraction) or dense (grain scaling).
    if (packing == "boundary-contraction")
      return dim == 3 ? 0.58 : 0.25;
    return dim == 3 ? 0.35 : 0.08;
  }

  void MaterialParams::validate(const std::string &where, int dim) const
  {
    const double inf = HUGE_VAL;
    if (type != "linear" && type != "contactbonded" && type != "parallelbonded" &&
        type != "flatjointed")
      fail(where, "type",
           "= '" + type +
               "' is not one of linear, contactbonded, parallelbonded, "
               "flatjointed");
    if (sizes.empty())
      fail(where, "sizes", "is empty: give at least one size distribution");
    double vf = 0;
    for (std::size_t j = 0; j < sizes.size(); ++j)
      {
        const auto       &s = sizes[j];
        const std::string k = "sizes[" + std::to_string(j) + "].";
        check_range(where, k + "volume_fraction", s.volume_fraction, 0, 1);
        vf += s.volume_fraction;
        if (s.gaussian)
          {
            check_range(where, k + "mean", s.mean, 0, inf, true);
            check_range(where, k + "sd", s.sd, 0, inf);
            if (s.d_hi > 0)
              {
                check_range(where, k + "d_lo", s.d_lo, 0, s.mean);
                check_range(where, k + "d_hi", s.d_hi, s.mean, inf);
              }
          }
        else
          {
            check_range(where, k + "d_lo", s.d_lo, 0, inf, true);
            check_range(where, k + "d_hi", s.d_hi, s.d_lo, inf);
          }
      }
    if (std::abs(vf - 1) > 1e-9)
      {
        std::ostringstream m;
        m << "(sizes[*].volume_fraction) sums to " << vf
          << "; the fractions must sum to 1";
        fail(where, "volume_fraction", m.str());
      }
    check_range(where, "diameter_multiplier", diameter_multiplier, 0, inf, true);
    check_range(where, "density", density, 0, inf, true);
    check_range(where, "local_damping", local_damping, 0, 0.7);
    check_range(where, "lnm_emod", lnm_emod, 0, inf, true);
    check_range(where, "lnm_krat", lnm_krat, 0, inf);
    check_range(where, "lnm_fric", lnm_fric, 0, inf);
    if (is_bonded())
      {
        check_range(where, "emod", emod, 0, inf, true);
        check_range(where, "krat", krat, 0, inf);
        check_range(where, "fric", fric, 0, inf);
        check_range(where, "igap", igap, 0, inf);
      }
    if (type == "contactbonded")
      {
        check_distribution(where, "cb_tens", cb_tens);
        check_distribution(where, "cb_shears", cb_shears);
      }
    if (type == "parallelbonded")
      {
        check_range(where, "pb_rmul", pb_rmul, 0, inf, true);
        check_range(where, "pb_bemod", pb_bemod, 0, inf, true);
        check_range(where, "pb_bkrat", pb_bkrat, 0, inf);
        check_range(where, "pb_mcf", pb_mcf, 0, 1);
        check_distribution(where, "pb_ten", pb_ten);
        check_distribution(where, "pb_coh", pb_coh);
        check_range(where, "pb_fa", pb_fa, 0, 90, false, true);
      }
    if (type == "flatjointed")
      {
        check_range(where, "fj_B", fj_B, 0, 1);
        check_range(where, "fj_G", fj_G, 0, 1);
        if (fj_B + fj_G > 1 + fraction_sum_tolerance)
          {
            std::ostringstream m;
            m << "(fj_B + fj_G = " << fj_B + fj_G
              << ") exceeds 1: the bonded, gapped and slit fractions must sum to 1 "
                 "(slit = 1 - B - G >= 0)";
            fail(where, "fj_G", m.str());
          }
        check_distribution(where, "fj_gap", fj_gap);
        if (fj_G > 0 && fj_gap.mean <= 0)
          fail(where, "fj_gap_m",
               "must be > 0 when fj_G > 0 (gapped joints have g_o > 0)");
        check_range(where, "fj_Nr", fj_Nr, 1, inf);
        if (dim == 3)
          check_range(where, "fj_Nal", fj_Nal, 3, inf);
        if (fj_rmul_code < 0 || fj_rmul_code > 2)
          fail(where, "fj_rmul_code",
               "= " + std::to_string(fj_rmul_code) + " is not 0, 1 or 2");
        check_range(where, "fj_rmul", fj_rmul, 0, inf, true);
        check_distribution(where, "fj_ten", fj_ten);
        check_distribution(where, "fj_coh", fj_coh);
        check_range(where, "fj_fa", fj_fa, 0, 90, false, true);
      }
    if (packing != "grain-scaling" && packing != "boundary-contraction")
      fail(where, "packing",
           "= '" + packing + "' is not one of grain-scaling, boundary-contraction");
    check_range(where, "Pm", Pm, 0, inf, true);
    check_range(where, "P_tol", P_tol, 0, 1, true, true);
    check_range(where, "ratio_limit", ratio_limit, 0, 1, true, true);
    check_range(where, "step_limit", static_cast<double>(step_limit), 1, inf);
    if (cloud_porosity >= 0)
      check_range(where, "cloud_porosity", cloud_porosity, 0, 1, false, true);
    check_range(where, "fric_CA", fric_CA, 0, inf);
    check_range(where, "v_limit", v_limit, 0, inf);
  }

  Random::Random(std::uint64_t seed)
      : gen_(seed)
  {
  }

  double Random::uniform()
  {
    // 53 random bits -> [0, 1), identical on every platform.
    return (gen_() >> 11) * (1.0 / 9007199254740992.0);
  }

  double Random::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  double Random::normal()
  {
    // Box-Muller (one value per call; the partner is discarded so the
    // sequence does not depend on call interleaving).
    double u1 = uniform();
    while (u1 <= 0)
      u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
  }

  double Random::truncated_normal(const Distribution &d)
  {
    if (d.sd <= 0)
      return d.mean;
    for (int i = 0; i < 1000; ++i)
      {
        const double x = d.mean + d.sd * normal();
        if (x > d.min)
          return x;
      }
    return std::max(d.mean, d.min);
  }

  std::uint64_t Random::index(std::uint64_t n)
  {
    return n == 0 ? 0
                  : static_cast<std::uint64_t>(uniform() * static_cast<double>(n)) % n;
  }
} // namespace demfem::dem
