#pragma once
// Material parameters of fistPkg §2 (Tables 1-5) and the packing parameters
// of §4.2.1 (Table 7), in SI units, with validation. Everything a FISHTank
// material file lists is representable here; the genesis (dem/specimen/genesis.h)
// turns them into a specimen.
#include "dem/engine/types.h"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace demfem::dem
{
  /// One piece of the grain-size distribution (fistPkg Table 1, footnote 9):
  /// uniform on [d_lo, d_hi] or Gaussian (mean, sd) truncated to [d_lo, d_hi]
  /// when d_hi > 0 (else to (0, mean + 4 sd]). Diameters [m] before the
  /// diameter multiplier.
  struct SizePiece
  {
    bool   gaussian        = false;
    double d_lo            = 0;
    double d_hi            = 0;
    double mean            = 0;
    double sd              = 0;
    double volume_fraction = 1; ///< fractions of all pieces sum to 1
  };

  /// Mean and standard deviation of a strength or gap distribution (normal,
  /// truncated at `min`, by default zero; sd = 0 gives the mean everywhere).
  /// A truncation point above zero keeps the weakest bonds out of a wide
  /// strength distribution (docs/calibrate_ldb.md, "Truncated strengths").
  struct Distribution
  {
    double mean = 0;
    double sd   = 0;
    double min  = 0; ///< draws at or below it are redrawn (0 <= min < mean)
  };

  /// Round-off allowed on phi_B + phi_G <= 1 (the rest slit): 0.9 and 0.1
  /// add up to more than one in binary.
  constexpr double fraction_sum_tolerance = 1e-12;

  struct MaterialParams
  {
    // ---- common (fistPkg Table 1) -----------------------------------------
    std::string type = "flatjointed"; ///< linear|contactbonded|parallelbonded|flatjointed
    std::vector<SizePiece> sizes;     ///< grain-size distribution
    double                 diameter_multiplier = 1; ///< D_mult (shifts the distribution)
    double                 density = 2650;          ///< grain (or bulk) density [kg/m^3]
    bool          bulk_density     = false; ///< density is the bulk density (C_p = 1)
    double        local_damping    = 0.7;
    std::uint64_t seed             = 10000; ///< pk_seed (affects packing)

    // ---- linear material group (Table 2; lnm_*), also new contacts --------
    double lnm_emod = 0; ///< E* [Pa]
    double lnm_krat = 0; ///< kappa*
    double lnm_fric = 0; ///< mu

    // ---- bonded-material linear group (cbm_/pbm_/fjm_ emod, krat, fric) ---
    double emod = 0; ///< E* of the bonded contacts [Pa]
    double krat = 0; ///< kappa*
    double fric = 0; ///< mu
    double igap = 0; ///< installation gap g_i [m]

    // ---- contact bond (Table 3) -------------------------------------------
    Distribution cb_tens;   ///< tensile strength [Pa]
    Distribution cb_shears; ///< shear strength [Pa]

    // ---- parallel bond (Table 4) ------------------------------------------
    double       pb_rmul  = 1; ///< radius multiplier
    double       pb_bemod = 0; ///< bond E* [Pa]
    double       pb_bkrat = 1; ///< bond kappa*
    double       pb_mcf   = 0; ///< moment-contribution factor
    Distribution pb_ten;       ///< tensile strength [Pa]
    Distribution pb_coh;       ///< cohesion [Pa]
    double       pb_fa = 0;    ///< friction angle [deg]

    // ---- flat joint (Table 5) ---------------------------------------------
    double       fj_B = 1;         ///< bonded fraction phi_B
    double       fj_G = 0;         ///< gapped fraction phi_G (slit = 1 - B - G)
    Distribution fj_gap;           ///< initial surface gap of gapped joints [m]
    int          fj_Nr        = 2; ///< elements radially (2D: total)
    int          fj_Nal       = 4; ///< elements circumferentially (3D)
    int          fj_rmul_code = 0; ///< 0 fixed, 1 valid non-uniform, 2 valid uniform
    double       fj_rmul      = 1; ///< fixed or starting radius multiplier
    Distribution fj_ten;           ///< tensile strength [Pa]
    Distribution fj_coh;           ///< cohesion [Pa]
    double       fj_fa = 0;        ///< friction angle [deg]

    // ---- packing (Table 7) ------------------------------------------------
    std::string  packing        = "grain-scaling"; ///< or "boundary-contraction"
    double       Pm             = 0;    ///< material pressure [Pa] (compression positive)
    double       P_tol          = 1e-2; ///< pressure tolerance eps_P
    double       ratio_limit    = 8e-3; ///< equilibrium-ratio limit (ft_eq)
    std::int64_t step_limit     = 2000000; ///< step limit (ft_eq)
    double       cloud_porosity = -1; ///< n_c; < 0: Table 7 default by method and dim
    double       fric_CA = 0; ///< friction during confinement (boundary contraction)
    double       v_limit = 0; ///< servo velocity limit [m/s]; 0: automatic

    bool is_bonded() const { return type != "linear"; }
    /// Throws InputError naming the key, `where` (file) and the allowed range.
    /// Run setting, not a property of the material: genesis refuses a
    /// specimen whose estimated memory exceeds it [bytes] (<= 0: half the
    /// machine's memory; dem/specimen/memory_budget.h).
    double memory_limit = 0;

    void validate(const std::string &where, int dim = 2) const;
    /// Table 7 default of n_c when cloud_porosity < 0.
    double cloud_porosity_or_default(int dim) const;
  };

  /// Portable random numbers (docs/architecture.md, "Random numbers"):
  /// mt19937_64 with our own transforms.
  class Random
  {
  public:
    explicit Random(std::uint64_t seed);
    double uniform();                     ///< [0, 1)
    double uniform(double lo, double hi); ///< [lo, hi)
    double normal();                      ///< standard normal (Box-Muller)
    /// One draw of d: the normal redrawn until above d.min (d.sd = 0: the
    /// mean).
    double        truncated_normal(const Distribution &d);
    std::uint64_t index(std::uint64_t n); ///< uniform in [0, n)

  private:
    std::mt19937_64 gen_;
  };
} // namespace demfem::dem
