#pragma once
// Bilinear-softening law of one local contact point of the Voronoi contact
// model (seed 004 §2.5-2.6, Fig. 3; docs/voronoi.md, "Softening law").
//
// Per unit area, in the normal direction: linear elastic (stiffness kn) up
// to the tensile strength sigma_t, then linear softening to zero stress at
// the opening 2 G_t / sigma_t, so the area under the curve is the tensile
// fracture energy G_t. In shear: linear elastic (ks = kn / kappa, seed 004
// eq. for the local stiffnesses) up to the Mohr-Coulomb strength
// c + mu sigma_c (sigma_c the compressive normal stress), then the cohesion
// part softens linearly to zero over the slip 2 G_s / c while the friction
// part stays. The two damages add (seed 004 §2.6): D = D_t + D_s <= 1, and
// the current strengths are (1 - D) sigma_t and (1 - D) c. At D = 1 the
// point is a local crack and purely frictional; its mode is tensile if the
// normal force was tensile when D reached 1, shear otherwise.
//
// Damage measure. The seed defines D_t from the current normal displacement
// and D_s from the current shear displacement along the softening branches
// of Fig. 3. Here they grow with the inelastic parts of those displacements,
// the crack opening w_n = u_n - F_n / (kn A) and the slip w_s, as
// dD_t = dw_n / w_nc and dD_s = dw_s / w_sc with w_nc = 2 G_t / sigma_t and
// w_sc = 2 G_s / c. On a monotonic softening branch both definitions give
// the same curve (the line from the peak to zero stress at u = w_nc is
// sigma = sigma_t (1 - w_n / w_nc)); the inelastic measure in addition makes
// unloading elastic (slope kn) and damage irreversible, and the return
// mapping below is exact for any step size, so the dissipated energy is
// G A to roundoff whatever the path. Under compression an open crack first
// closes without force (w_n returns to 0, the faces meet at the installed
// position), so a cracked point is the linear no-tension contact. Under
// combined loading the normal direction is corrected first and the shear
// direction with the damage that results (operator split).
//
// Brittle limit. With G_t = sigma_t^2 / (2 kn) (the elastic energy at the
// peak) w_nc equals the elastic opening at the peak, the softening branch
// is vertical, and the first step beyond the peak breaks the point: the
// brittle tension cut-off. Likewise G_s = c^2 / (2 ks) gives the brittle
// Mohr-Coulomb law with a residual friction. Smaller fracture energies
// (snap-back) are rejected.
//
// Sign conventions as dem/engine/contact_law.h: u_n > 0 and F_n > 0 are opening
// and tension; F_s is the shear force on grain B along the contact tangent.
#include "dem/engine/types.h"

#include <cmath>
#include <string>

namespace demfem::dem::voronoi
{
  /// Contact material of the Voronoi contact model, per unit contact area
  /// (seed 004 §2.5).
  struct ContactMaterial
  {
    double kn                      = 0; ///< normal stiffness per unit area [Pa/m]
    double kratio                  = 1; ///< kappa: ks = kn / kappa
    double tensile_strength        = 0; ///< sigma_t [Pa]
    double cohesion                = 0; ///< c [Pa]
    double friction                = 0; ///< mu (the seed's frictional term)
    double tensile_fracture_energy = 0; ///< G_t [J/m^2], >= sigma_t^2/(2 kn)
    double shear_fracture_energy   = 0; ///< G_s [J/m^2], >= c^2/(2 ks)
    double thickness               = 1; ///< out-of-plane thickness t [m]
    /// Deformability mode (docs/voronoi.md, "Contact stiffness"): E_c > 0
    /// sets kn = E_c / d per contact, d the distance of the two disk
    /// centres (the rigid-body-spring network of Voronoi cells is then
    /// elastically uniform for kappa = 1: a uniform strain is in equilibrium
    /// with sigma = E_c eps, nu = 0); `kn` is then not used. In this mode a
    /// fracture energy of 0 means the brittle value of each contact.
    double contact_modulus = 0; ///< E_c [Pa]; 0: the uniform kn above

    bool deformability_mode() const { return contact_modulus > 0; }
    /// The material of one contact whose spring spans the length d: kn =
    /// E_c / d (deformability mode; zero fracture energies set to the
    /// contact's brittle values), or this material unchanged.
    ContactMaterial for_length(double d) const
    {
      if (!deformability_mode())
        return *this;
      ContactMaterial m = *this;
      m.kn              = contact_modulus / d;
      m.contact_modulus = 0;
      if (m.tensile_fracture_energy == 0)
        m.tensile_fracture_energy = m.tensile_elastic_energy();
      if (m.shear_fracture_energy == 0)
        m.shear_fracture_energy = m.shear_elastic_energy();
      return m;
    }

    double ks() const { return kn / kratio; }
    /// Elastic energy per unit area at the tensile peak, sigma_t^2 / (2 kn):
    /// the brittle value of G_t.
    double tensile_elastic_energy() const
    {
      return tensile_strength * tensile_strength / (2 * kn);
    }
    /// Elastic energy per unit area at the cohesive peak, c^2 / (2 ks).
    double shear_elastic_energy() const { return cohesion * cohesion / (2 * ks()); }
    /// This material with G_t and G_s at their brittle values.
    ContactMaterial brittle() const
    {
      ContactMaterial m         = *this;
      m.tensile_fracture_energy = tensile_elastic_energy();
      m.shear_fracture_energy   = shear_elastic_energy();
      return m;
    }

    void validate(const std::string &where) const
    {
      const double inf = HUGE_VAL;
      if (deformability_mode())
        {
          // kn and the fracture-energy bounds are per contact (for_length).
          check_range(where, "contact_modulus", contact_modulus, 0, inf, true, true);
          check_range(where, "kratio", kratio, 0, inf, true, true);
          check_range(where, "tensile_strength", tensile_strength, 0, inf, false, true);
          check_range(where, "cohesion", cohesion, 0, inf, false, true);
          check_range(where, "friction", friction, 0, inf, false, true);
          check_range(where, "thickness", thickness, 0, inf, true, true);
          check_range(where, "tensile_fracture_energy", tensile_fracture_energy, 0, inf,
                      false, true);
          check_range(where, "shear_fracture_energy", shear_fracture_energy, 0, inf,
                      false, true);
          return;
        }
      check_range(where, "kn", kn, 0, inf, true, true);
      check_range(where, "kratio", kratio, 0, inf, true, true);
      check_range(where, "tensile_strength", tensile_strength, 0, inf, false, true);
      check_range(where, "cohesion", cohesion, 0, inf, false, true);
      check_range(where, "friction", friction, 0, inf, false, true);
      check_range(where, "thickness", thickness, 0, inf, true, true);
      // Fracture energies below the elastic energy at the peak would need a
      // snap-back; 1e-9 relative lets the brittle value through roundoff.
      check_range(where, "tensile_fracture_energy", tensile_fracture_energy,
                  tensile_elastic_energy() * (1 - 1e-9), inf, false, true);
      check_range(where, "shear_fracture_energy", shear_fracture_energy,
                  shear_elastic_energy() * (1 - 1e-9), inf, false, true);
    }
  };

  /// Crack state of a local contact point.
  enum class PointCrack : signed char
  {
    intact   = 0, ///< D < 1
    tensile  = 1, ///< D reached 1 under tension
    shear    = 2, ///< D reached 1 under compression (or zero normal force)
    unbonded = 3  ///< no strength from the start (sigma_t = c = 0)
  };

  /// Constants derived once from a ContactMaterial (per unit area).
  struct SofteningCoefficients
  {
    double kn = 0, ks = 0, sigma_t = 0, cohesion = 0, friction = 0;
    double w_nc = 0; ///< crack opening at D_t = 1, 2 G_t / sigma_t
    double w_sc = 0; ///< slip at D_s = 1, 2 G_s / c
    /// kn - sigma_t / w_nc and ks - c / w_sc: the denominators of the return
    /// mapping; 0 marks the brittle limit (vertical softening branch).
    double kn_soft = 0, ks_soft = 0;

    static SofteningCoefficients derive(const ContactMaterial &m)
    {
      m.validate("Voronoi contact material");
      SofteningCoefficients k;
      k.kn       = m.kn;
      k.ks       = m.ks();
      k.sigma_t  = m.tensile_strength;
      k.cohesion = m.cohesion;
      k.friction = m.friction;
      k.w_nc     = k.sigma_t > 0 ? 2 * m.tensile_fracture_energy / k.sigma_t : 0;
      k.w_sc     = k.cohesion > 0 ? 2 * m.shear_fracture_energy / k.cohesion : 0;
      // Within 1e-9 of the brittle value (roundoff of 2 G / sigma) the
      // softening slope is taken as vertical.
      k.kn_soft = k.sigma_t > 0 ? k.kn - k.sigma_t / k.w_nc : 0;
      k.ks_soft = k.cohesion > 0 ? k.ks - k.cohesion / k.w_sc : 0;
      if (k.kn_soft <= 1e-9 * k.kn)
        k.kn_soft = 0;
      if (k.ks_soft <= 1e-9 * k.ks)
        k.ks_soft = 0;
      return k;
    }

    /// Initial crack state of a new point.
    PointCrack initial_crack() const
    {
      return sigma_t == 0 && cohesion == 0 ? PointCrack::unbonded : PointCrack::intact;
    }
  };

  /// State of one local contact point (the contact set stores these fields
  /// as arrays; this is the view the law works on).
  struct PointState
  {
    double     &un;       ///< normal displacement since install, > 0 opening
    double     &wn;       ///< inelastic opening (crack opening)
    double     &fs;       ///< shear force on grain B along the tangent
    double     &damage_t; ///< D_t
    double     &damage_s; ///< D_s
    PointCrack &crack;
  };

  /// Advances one point by the displacement increments (d_un opening,
  /// d_us shear of grain B relative to A along the tangent) for a point of
  /// area A; returns the normal force F_n (> 0 tension). Allocation free.
  inline double update_point(const SofteningCoefficients &k, double A, double d_un,
                             double d_us, PointState s)
  {
    s.un += d_un;
    // ---- normal (tension cut-off with softening) ---------------------------
    // A cracked point has D = 1 whatever roundoff left in D_t + D_s.
    auto damage = [&]() {
      return s.crack != PointCrack::intact ? 1.0 : std::min(1.0, s.damage_t + s.damage_s);
    };
    double D  = damage();
    double fn = k.kn * A * (s.un - s.wn);
    // Closing an open crack costs no force until its faces touch again at
    // the installed position (u_n = 0); then compression as before.
    if (fn < 0 && s.wn > 0)
      {
        s.wn = std::max(0.0, s.un);
        fn   = k.kn * A * (s.un - s.wn);
      }
    const double T         = (1 - D) * k.sigma_t * A;
    auto         crack_now = [&](bool tensile) {
      if (s.crack == PointCrack::intact)
        s.crack = tensile ? PointCrack::tensile : PointCrack::shear;
    };
    if (fn > T)
      {
        double dw = HUGE_VAL; // inelastic opening of this step
        if (D < 1 && k.kn_soft > 0)
          dw = (fn - T) / (k.kn_soft * A);
        if (dw < (1 - D) * k.w_nc)
          {
            s.wn += dw;
            s.damage_t += dw / k.w_nc;
          }
        else
          {
            // Full damage (or already cracked): the point opens freely.
            if (D < 1)
              s.damage_t = 1 - s.damage_s;
            s.wn = s.un;
            crack_now(true);
          }
        fn = k.kn * A * (s.un - s.wn);
        D  = damage();
      }
    // ---- shear (Mohr-Coulomb with cohesion softening) ----------------------
    const double trial = s.fs - k.ks * A * d_us;
    const double mag   = std::abs(trial);
    const double sign  = trial < 0 ? -1.0 : 1.0;
    const double fric  = -k.friction * fn; // friction part (< 0 in tension)
    const double S     = std::max(0.0, (1 - D) * k.cohesion * A + fric);
    if (mag <= S)
      {
        s.fs = trial;
        return fn;
      }
    if (D < 1 && k.cohesion > 0)
      {
        // Slip dw of this step softens the cohesion; on the softening line
        // |trial| - ks A dw = (1 - D - dw / w_sc) c A + fric. In tension the
        // strength can reach zero before D = 1: from there on the slip is
        // free (force 0) and all of the trial displacement is slip.
        double dw = HUGE_VAL, f_new = 0; // brittle (ks_soft = 0): breaks
        if (k.ks_soft > 0)
          {
            dw    = S > 0 ? (mag - S) / (k.ks_soft * A) : mag / (k.ks * A);
            f_new = S > 0 ? mag - k.ks * A * dw : 0.0;
            if (f_new < 0)
              {
                dw    = mag / (k.ks * A);
                f_new = 0;
              }
          }
        if (dw < (1 - D) * k.w_sc)
          {
            s.damage_s += dw / k.w_sc;
            s.fs = sign * f_new;
            return fn;
          }
        s.damage_s = 1 - s.damage_t;
        crack_now(fn > 0);
      }
    // Purely frictional (cracked, or no cohesion).
    s.fs = sign * std::max(0.0, fric);
    return fn;
  }
} // namespace demfem::dem::voronoi
