#pragma once
// In-situ stress servo: the stress-controlled end of the kinematic in-situ
// installation (docs/tunnel.md, "In-situ stress servo").
//
// Why. The kinematic installation (coupled_model.h) gives the region the
// strain eps0 of sigma0 in the continuum's constants, the material file's
// E and nu. The region's own response differs by its packing (the probe
// reads E and nu within 5 %), and a lateral stress is mostly carried by
// the Poisson effect: on the default example the relaxed region carried
// sigma_xx = -9.07 MPa for -10 (in_situ_error 2.3 %), the response of a
// Poisson ratio 0.25 instead of the file's 0.264. Released together, the
// region and the continuum meet at the Eshelby state of an inclusion of
// other constants, which is not sigma0 on either side.
//
// How. The continuum is held on the affine path at lambda = 1 (it carries
// sigma0 exactly and does not move), the grains are released and relaxed
// with their boundary at eps0 X, and the region's centre-disk stress
// sigma_r (the stress the run reports before excavation) is measured. The
// interface strain E (CoupledModel::set_interface_strain: the DEM side of
// the interface at u + E X, an eigenstrain of the region relative to the
// continuum, as the initial-stress state of geomechanics is the reference
// of the displacements) is then corrected with the region's own stiffness:
//   E <- E + C_r^-1 (sigma0 - sigma_r),
// C_r the isotropic in-plane stiffness fitted to the first measurement
// (sigma_r = C_r eps0: mean part (lambda + mu) tr eps, deviatoric part
// 2 mu dev eps; the continuum's part where eps0 has none), and the change
// is applied over one crossing time of the region with the free grains on
// its affine path, then relaxed to equilibrium again. With the continuum
// held the region answers with its own stiffness, so each iteration leaves
// the part of the error its anisotropy and heterogeneity do not fit (a
// chord iteration). It stops once the error is within the tolerance, or
// after max_iterations corrections. The continuum is then released; its
// stress is sigma0 and the grains' tractions are sigma0 n in the mean, so
// the release moves little. A large |E| / |eps0| means the region is not
// the continuum's material (summary.json reports it; warned above
// contrast_warning).
#include "coupling/tunnel_result.h"
#include "dem/io/state_archive.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace demfem::coupling
{
  class InSituServo
  {
  public:
    /// Corrections at most: the chord iteration shrinks the error by the
    /// region's anisotropy per step (measured: a factor 10-40 on the
    /// default example), so six leave room for a strongly anisotropic
    /// packing; one that needs more is reported by its error.
    static constexpr std::size_t max_iterations = 6;
    /// |E| / |eps0| above which the run warns that the region's stiffness
    /// is not the continuum's. The probe accepts E and nu within 5 % each,
    /// which alone moves a Poisson-carried lateral strain by up to about
    /// 10 %; and the region is installed intact (bond breakage suspended)
    /// while the file's E, nu are secant lab values at half the strength,
    /// past the first cracks: the default example's region reads mu 19 %
    /// above the file's, |E| / |eps0| = 12.7 %. Twice that is a region
    /// that is not the material.
    static constexpr double contrast_warning = 0.25;
    /// |E| / |eps0| beyond which the in-situ state counts as not reached
    /// (tunnel_result.h, assess_outcome): the region's stiffness differs
    /// from the continuum's by about a factor 2 (stiffer; 1.5 softer), so
    /// the continuum around it is another material and the excavation's
    /// answer is not the material's.
    static constexpr double contrast_limit = servo_contrast_limit;
    /// Lower bound of the fitted stiffness relative to the continuum's.
    static constexpr double min_stiffness_ratio = 0.05;

    struct Iteration
    {
      Eigen::Matrix2d strain;    ///< interface strain E at the measurement
      Eigen::Matrix2d stress;    ///< centre-disk stress at equilibrium [Pa]
      double          error = 0; ///< in_situ_error of stress
    };

    /// `tolerance` (Tunnel/in situ servo tolerance; 0: off), the in-situ
    /// stress and the continuum's strain of it (in plane), the continuum's
    /// E and nu (the plane-strain relation of coupled_model.cc).
    InSituServo(double tolerance, const Eigen::Matrix2d &sigma0,
                const Eigen::Matrix2d &eps0, double young, double poisson)
        : tol(tolerance)
        , s0(sigma0)
        , e0(eps0)
        , mean_modulus(young / (2 * (1 + poisson) * (1 - 2 * poisson))) // lambda + mu
        , shear_modulus(young / (2 * (1 + poisson)))
        , continuum_mean(mean_modulus)
        , continuum_shear(shear_modulus)
    {
    }

    double tolerance() const { return tol; }

    /// Records the centre-disk stress measured at equilibrium with the
    /// interface strain E; the first record fits the region's stiffness.
    /// Returns whether the servo is done (within tolerance, or out of
    /// iterations).
    bool record(const Eigen::Matrix2d &stress, const Eigen::Matrix2d &E)
    {
      if (history.empty())
        fit_stiffness(stress);
      history.push_back({E, stress, in_situ_error(stress, s0)});
      return converged() || history.size() > max_iterations;
    }

    bool converged() const { return !history.empty() && history.back().error <= tol; }

    /// The next interface strain after the latest record.
    Eigen::Matrix2d next_strain() const
    {
      const Iteration      &last = history.back();
      const Eigen::Matrix2d ds   = s0 - last.stress;
      const double          mean = 0.5 * ds.trace();
      const Eigen::Matrix2d dev  = ds - mean * Eigen::Matrix2d::Identity();
      // sigma_mean = (lambda + mu) tr eps, dev sigma = 2 mu dev eps.
      return last.strain + dev / (2 * shear_modulus) +
             0.5 * mean / mean_modulus * Eigen::Matrix2d::Identity();
    }

    const std::vector<Iteration> &iterations() const { return history; }
    /// The fitted in-plane stiffness relative to the continuum's:
    /// {(lambda + mu)_region / (lambda + mu), mu_region / mu}.
    std::array<double, 2> stiffness_ratios() const
    {
      return {{mean_modulus / continuum_mean, shear_modulus / continuum_shear}};
    }
    /// |E| / |eps0| (Frobenius norms) of the latest record.
    double relative_strain() const
    {
      return history.empty() || e0.norm() == 0 ? 0.0
                                               : history.back().strain.norm() / e0.norm();
    }

    /// The ramp of the current correction (from, to), kept for a restart.
    Eigen::Matrix2d from = Eigen::Matrix2d::Zero(), to = Eigen::Matrix2d::Zero();

    /// Checkpoint entries (one function for saving and loading).
    void serialize(dem::StateArchive &ar)
    {
      std::vector<double> flat;
      if (!ar.loading())
        for (const auto &it : history)
          {
            for (int k = 0; k < 4; ++k)
              flat.push_back(it.strain(k));
            for (int k = 0; k < 4; ++k)
              flat.push_back(it.stress(k));
            flat.push_back(it.error);
          }
      ar.io("run.servo_iterations", flat);
      if (ar.loading())
        {
          history.clear();
          for (std::size_t i = 0; i + 9 <= flat.size(); i += 9)
            {
              Iteration it;
              for (int k = 0; k < 4; ++k)
                it.strain(k) = flat[i + k];
              for (int k = 0; k < 4; ++k)
                it.stress(k) = flat[i + 4 + k];
              it.error = flat[i + 8];
              history.push_back(it);
            }
        }
      ar.io("run.servo_mean_modulus", mean_modulus);
      ar.io("run.servo_shear_modulus", shear_modulus);
      ar.io("run.servo_from", from);
      ar.io("run.servo_to", to);
    }

  private:
    double                 tol;
    Eigen::Matrix2d        s0, e0;
    double                 mean_modulus, shear_modulus, continuum_mean, continuum_shear;
    std::vector<Iteration> history;

    // sigma_r = C_r eps0 with C_r isotropic in plane: the mean part gives
    // lambda + mu, the deviatoric part mu; a part eps0 lacks (hydrostatic
    // or traceless sigma0) keeps the continuum's value. Bounded below by
    // min_stiffness_ratio times the continuum's (also a fit of the wrong
    // sign or not finite): a region that does not answer then gets
    // corrections of at most 1 / min_stiffness_ratio times eps0, which
    // undershoot, never overshoot. No upper bound: an underestimated
    // stiffness overshoots by the ratio, and a region 10^4 times stiffer
    // than the continuum (tests/fault_injection.sh) diverged with one.
    void fit_stiffness(const Eigen::Matrix2d &stress)
    {
      const double          size    = e0.norm();
      const double          tr      = e0.trace();
      const Eigen::Matrix2d dev     = e0 - 0.5 * tr * Eigen::Matrix2d::Identity();
      const auto            bounded = [](double v, double c) {
        return std::isfinite(v) ? std::max(v, min_stiffness_ratio * c)
                                           : min_stiffness_ratio * c;
      };
      if (std::abs(tr) > 1e-3 * size)
        mean_modulus = bounded(0.5 * stress.trace() / tr, continuum_mean);
      if (dev.norm() > 1e-3 * size)
        {
          const Eigen::Matrix2d s =
              stress - 0.5 * stress.trace() * Eigen::Matrix2d::Identity();
          shear_modulus = bounded(
              (s.array() * dev.array()).sum() / (2 * dev.squaredNorm()), continuum_shear);
        }
    }
  };
} // namespace demfem::coupling
