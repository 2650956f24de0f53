#pragma once
// `demfem study` (docs/architecture.md, "Speed-versus-accuracy study"):
// speed-versus-accuracy sweep of the elastic embedded tunnel, stability map of
// the scheme settings, and right-sizing of the DEM region by a Kirsch elastic
// pre-analysis.
#include <deal.II/base/parameter_handler.h>

#include "apps/tunnel_prm.h"
#include "common/statistics.h"
#include "coupling/full_dem_reference.h"
#include "coupling/tunnel_run.h"

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::apps::study
{
  /// The `Study` subsection: the values to sweep and the right-sizing
  /// criterion. An empty list keeps the value of the tunnel keys.
  struct Settings
  {
    std::vector<std::optional<double>> radius_factors; ///< x tunnel radius; nullopt: auto
    std::vector<double>                resolutions;    ///< a/d
    std::vector<unsigned int>          subcycles;
    std::vector<double>                safeties;
    std::vector<std::uint64_t>         seeds;       ///< packing seeds (error averages)
    std::vector<std::string>           variants;    ///< Coupling/variant values
    std::vector<std::string>           schemes;     ///< Coupling/scheme values
    std::vector<double>                relaxations; ///< Coupling/relaxation values
    /// Continuum/young modulus = this x the material's E (DEM/continuum
    /// stiffness contrast; 1: matched constants)
    std::vector<double> stiffness_contrasts;
    /// Breakable mode: the embedded runs use breakable bonds and are compared
    /// with a full-DEM reference on damage-zone depth and crack counts instead
    /// of Kirsch.
    bool   breakable               = false;
    double reference_radius_factor = 8;    ///< reference domain radius / a (>= 8)
    double servo_tolerance         = 0.02; ///< membrane servo: held-stress tolerance
    double agreement_tolerance     = 0.1;  ///< equal damage-zone depth: within +-this
    double damage_fraction = 0.4; ///< damage initiation: sigma1 - sigma3 >= this x UCS
    double ucs             = 0;   ///< [Pa]; 0: "ucs" of the DEM region's material file
    double margin_grains   = 3;   ///< auto radius = damage radius + this x d
  };
  void declare_study_parameters(dealii::ParameterHandler &prm);
  /// `material_file`: 'DEM region/material file' (for its "ucs").
  Settings read_study_settings(dealii::ParameterHandler &prm,
                               const std::string        &material_file);

  // --- Kirsch (plane strain, linear elastic, infinite medium; tension positive)

  /// Mean over theta of the excavation-induced inward radial displacement of
  /// the wall r = a: u = -a (sxx + syy) / (4 G), G = E / (2 (1 + nu)).
  double kirsch_mean_convergence(const Eigen::Matrix2d &sigma0, double a, double E,
                                 double nu);
  /// The same, evaluated where the measured wall grains are: the mean over
  /// `points` (reference x, y; r >= a) of Kirsch's excavation-induced inward
  /// radial displacement, u_r = a^2/(4 G r) [(S1 + S2) + (S1 - S2)
  /// (4 (1 - nu) - a^2/r^2) cos 2 (theta - phi)] (tension positive, plane
  /// strain). On r = a it is kirsch_mean_convergence's integrand.
  double kirsch_convergence_at(const Eigen::Matrix2d &sigma0, double a, double E,
                               double                                    nu,
                               const std::vector<std::array<double, 2>> &points);
  /// In-plane differential stress sigma1 - sigma3 of the Kirsch field at
  /// (r, theta), theta from the x axis.
  double kirsch_differential_stress(const Eigen::Matrix2d &sigma0, double a, double r,
                                    double theta);
  /// Largest r with max_theta (sigma1 - sigma3) >= threshold (a if none).
  /// Throws dem::InputError if the far field itself reaches the threshold.
  double kirsch_damage_radius(const Eigen::Matrix2d &sigma0, double a, double threshold);

  struct AutoRadius
  {
    double threshold = 0, damage_radius = 0, radius = 0;
  };
  /// Right-sizing: region radius = damage radius + margin_grains x d, and at
  /// least a + 4 d (the tunnel run needs >= 3 grains around the tunnel).
  AutoRadius auto_region_radius(const Eigen::Matrix2d &sigma0, double a, double ucs,
                                double fraction, double margin_grains, double d);

  // --- results

  /// Only the quasi-static scheme relaxes its interface displacement; the
  /// explicit and condensed schemes never read Coupling/relaxation, so the
  /// sweep runs them once and their rows are not part of the relaxation
  /// axis (of the stability map or of study.csv).
  inline bool uses_relaxation(const std::string &scheme)
  {
    return scheme == "quasi-static";
  }

  struct Row
  {
    int           index         = 0;
    double        region_radius = 0, region_factor = 0, resolution = 0, grain_d = 0;
    bool          region_auto = false;
    unsigned int  subcycles   = 1;
    double        safety      = 0;
    std::string   variant, scheme;
    double        relaxation = 1, contrast = 1; ///< contrast: E_continuum / E_material
    std::uint64_t seed = 0;
    std::string   status; ///< stable | unstable | invalid
    std::string   diagnosis;
    coupling::TunnelResult result;
    double                 kirsch = 0, error = 0; ///< error: relative, signed
    /// Kirsch where the wall grains are (kirsch_convergence_at) and the
    /// error against it: free of the O(d/a) offset of the grains' centres
    /// lying up to a diameter outside the wall (docs/study.md).
    double kirsch_at_grains = 0, error_at_grains = 0;
    bool   pareto       = false;
    double final_ratio  = -1;    ///< last unbalanced ratio (history.csv); -1 unknown
    bool   equilibrated = false; ///< final ratio <= Coupling/equilibrium ratio
    // Breakable mode: `error` is the relative difference of the damage-zone
    // depth from the reference's (NaN without a usable reference).
    bool        breakable         = false;
    int         reference         = -1;    ///< index of its full-DEM reference
    std::size_t cracks_excavation = 0;     ///< cracks from the excavation on
    bool        region_too_small  = false; ///< cracks near the coupling boundary
    double      reference_depth   = 0;     ///< damage-zone depth of the reference [m]
    double      cracks_diff       = 0; ///< relative difference of the excavation cracks
    double      reference_area    = 0; ///< damaged area of the reference [m^2]
    /// Relative difference of the damaged area from the reference's (NaN
    /// when the reference has no damaged area).
    double area_diff = 0;
    /// |error| and |area_diff| <= Study/agreement tolerance, and not
    /// region_too_small: the same depth and the same damaged area.
    bool agrees = false;
  };

  /// One full-DEM reference run (per grain resolution and seed).
  struct Reference
  {
    double        resolution = 0;
    std::uint64_t seed       = 0;
    std::string   directory, status,
        diagnosis; ///< status: ok | diverged | invalid | not equilibrated
    coupling::FullDemReferenceResult result;
    std::size_t                      cracks_excavation() const
    {
      return result.cracks_total - result.cracks_before_excavation;
    }
    bool usable() const { return status == "ok" && result.damage_zone_depth > 0; }
  };

  /// Where a smaller region starts to change the answer: the smallest region
  /// factor from which every larger swept factor agrees with the reference
  /// (-1: none), and the largest disagreeing factor (-1: none); a factor's
  /// runs are pooled over seeds and other settings (RegionAnswer::rule).
  struct RegionAnswer
  {
    double smallest_agreeing = -1, largest_disagreeing = -1;
    /// "confidence": two seeds or more per factor, means within the
    /// references' 95 % intervals of depth and damaged area; "tolerance":
    /// one seed, depth within Study/agreement tolerance.
    std::string rule = "tolerance";
  };
  RegionAnswer region_answer(const std::vector<Row>       &rows,
                             const std::vector<Reference> &refs, double tolerance);
  /// The embedded runs of one setting over packing seeds (breakable mode),
  /// with the seed statistics (mean, 95 % interval; common/statistics.h) of
  /// their measures and of the references of the same seeds.
  struct SeedGroup
  {
    std::vector<const Row *> runs;
    statistics::Interval     depth, ref_depth, area, ref_area, notch, ref_notch, time,
        ref_time;
    std::size_t too_small = 0; ///< runs that are region_too_small
  };
  /// The settings with two seeds or more (stable, equilibrated runs with a
  /// usable reference).
  std::vector<SeedGroup> seed_groups(const std::vector<Row>       &rows,
                                     const std::vector<Reference> &refs);
  /// study_seeds.svg: per setting, mean wall time against the signed
  /// relative difference of the mean damage-zone depth (top panel) and of
  /// the mean damaged area (bottom panel) from the references' means, with
  /// the 95 % interval of the embedded mean as a bar and the references'
  /// interval as a band around zero.
  void write_seed_chart(const std::string &file, const std::vector<SeedGroup> &groups);
  /// study_speedup.csv and study.md: embedded wall time over the reference
  /// wall time for the runs that agree on the damage-zone depth; returns the
  /// number of table rows.
  std::size_t write_speedup(const std::string &csv, const std::string &markdown,
                            const std::vector<Row>       &rows,
                            const std::vector<Reference> &refs, double tolerance,
                            const RegionAnswer &answer);

  /// Marks the stable, equilibrated rows on the Pareto front of (wall time, |error|).
  void mark_pareto(std::vector<Row> &rows);
  void write_csv(const std::string &file, const std::vector<Row> &rows);
  /// Wall time versus |error| (log-log), Pareto front marked; plain SVG.
  /// Breakable mode: |error| is the damage-zone depth difference from the
  /// reference, whose wall time is drawn as a vertical line (ref_time > 0).
  void write_chart(const std::string &file, const std::vector<Row> &rows,
                   bool breakable = false, double ref_time = 0);
} // namespace demfem::apps::study
