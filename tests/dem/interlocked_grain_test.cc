// Interlocked grain (memo 000 §2.2, Figures 24-25) run through the engine:
// a central faced grain with four surrounding grains joined by unbonded,
// frictionless flat joints (memo Eq. 67). Phase 1 rotates the central grain
// counter-clockwise with all other grains fixed; phase 2 stops it and frees
// the rotation of the surrounding grains.
#include "dem/laws/flat_joint_law.h"
#include "dem/engine/model.h"

#include <catch2/catch.hpp>
#include <omp.h>

#include <cmath>
#include <vector>

using namespace demfem::dem;

namespace
{
  /// Five grains: one thread avoids the OpenMP fork/join cost per step, which
  /// dominates (x30 wall time) on a loaded machine. Restores the old count.
  struct SingleThread
  {
    int old = omp_get_max_threads();
    SingleThread() { omp_set_num_threads(1); }
    ~SingleThread() { omp_set_num_threads(old); }
  };

  constexpr double r_grain = 6.25e-3; // memo §2.2: R = lambda r = 5 mm
  constexpr double density = 2650;
  constexpr double theta   = 0.01; // imposed rotation of the central grain [rad]

  template <int dim>
  typename FlatJointLaw<dim>::Params eq67()
  {
    typename FlatJointLaw<dim>::Params p;
    p.Nr     = dim == 2 ? 4 : 2;
    p.Nal    = 8;
    p.rmul   = 0.8;
    p.gap0   = 0;
    p.fric   = 0;
    p.bonded = false; // B = 0 for all elements, sigma_c = c = phi = 0
    p.kn     = 2.32e12;
    p.ks     = 1.0087e12;
    return p;
  }

  /// z component of a rotation-like vector.
  template <int dim>
  double z_of(const RotVec<dim> &w)
  {
    return w[rot_dim<dim> - 1];
  }

  template <int dim>
  void set_z(RotVec<dim> &w, double v)
  {
    w.setZero();
    w[rot_dim<dim> - 1] = v;
  }

  template <int dim>
  struct Interlocked
  {
    Model<dim>                         m;
    typename FlatJointLaw<dim>::Params p = eq67<dim>();
    int                                g = -1;
    std::vector<ContactRef>            c;
    double                             dt = 0;

    Interlocked()
    {
      // Central grain 0, then +x, -x, +y, -y neighbours "just touching".
      const double off[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      m.particles.add(Vec<dim>::Zero(), r_grain, density);
      for (auto &o : off)
        {
          Vec<dim> x = Vec<dim>::Zero();
          x[0]       = 2 * r_grain * o[0];
          x[1]       = 2 * r_grain * o[1];
          m.particles.add(x, r_grain, density);
        }
      m.local_damping = 0.7;
      g               = m.template add_law<FlatJointLaw<dim>>(p);
      for (std::uint32_t j = 1; j <= 4; ++j)
        c.push_back(m.install(0, j, g));
      for (std::size_t i = 0; i < m.particles.size(); ++i)
        m.particles.fixity[i] = fix_all;
      // Everything fixed: the engine's estimate is infinite. Take 0.1 of the
      // translational period sqrt(m / (kn A)) of one face (memo §1.12).
      const double R = p.rmul * r_grain;
      const double A = dim == 2 ? 2 * R : M_PI * R * R;
      dt             = 0.1 * std::sqrt(m.particles.mass[0] / (p.kn * A));
      m.set_timestep(dt);
    }

    const double *state(int k) { return m.group(g).state(c[k].index); }
  };

  /// Phase-1 resisting moment of one unbonded face (closed form).
  /// 2D: g(rho) = g_s - rho theta_bk with g_s = 0 and theta_bk = -theta
  /// (piece 2 = neighbour fixed, piece 1 = centre turning by +theta), so
  /// g = rho theta is closed for rho in [-R, 0] only. The stress kn g acts at
  /// arm rho, so the moment on the centre is
  ///   -kn theta int_{-R}^{0} rho^2 drho = -kn theta R^3 / 3.
  /// 3D (memo Eq. 21, element scheme Eq. 32 with the centroid gap): with
  /// theta_b = -theta k, g(s, t) = s theta (s = projection of the face on the
  /// in-plane axis), closed for s^(e) < 0, and
  ///   M = -kn theta sum_{s^(e) < 0} A^(e) (s^(e))^2.
  /// The element centroids and areas are recomputed here from memo Eq. 16-17.
  /// The s axis is global y for the x neighbours and global x for the y
  /// neighbours (memo §1.3.1); either way the closed half is a half disk and
  /// the sum is the same because the N_alpha = 8 sectors are symmetric under
  /// s -> -s.
  template <int dim>
  double face_moment_closed_form(const typename FlatJointLaw<dim>::Params &p, double R)
  {
    if constexpr (dim == 2)
      {
        return -p.kn * theta * R * R * R / 3.0;
      }
    else
      {
        double       sum = 0;
        const double dr = R / p.Nr, da = 2 * M_PI / p.Nal;
        for (int e = 1; e <= p.Nr * p.Nal; ++e)
          {
            const int    I = (e - 1) / p.Nal, J = e - 1 - I * p.Nal;
            const double r1 = I * dr, r2 = (I + 1) * dr, a1 = J * da, a2 = (J + 1) * da;
            const double A = 0.5 * (a2 - a1) * (r2 * r2 - r1 * r1);
            const double s = 2.0 / 3.0 * (std::sin(a2) - std::sin(a1)) / (a2 - a1) *
                             (r2 * r2 * r2 - r1 * r1 * r1) / (r2 * r2 - r1 * r1);
            if (s < 0)
              sum += A * s * s;
          }
        return -p.kn * theta * sum;
      }
  }

  template <int dim>
  void run_interlocked()
  {
    SingleThread     one;
    Interlocked<dim> s;
    auto            &m     = s.m;
    const auto      &p     = s.p;
    using FJ               = FlatJointLaw<dim>;
    const int    nsteps    = 1000;
    const double omega     = theta / (nsteps * s.dt);
    const double R         = p.rmul * r_grain;
    const int    nelements = dim == 2 ? p.Nr : p.Nr * p.Nal;

    // ---- phase 1: rotate the central grain counter-clockwise -------------
    set_z<dim>(m.particles.w[0], omega);
    m.cycle(nsteps);
    // All central-difference increments are w dt: the accumulated relative
    // bend equals theta to round-off.
    const double Mface = face_moment_closed_form<dim>(s.p, R);
    double       fn_phase1[4];
    for (int k = 0; k < 4; ++k)
      {
        const auto        &G  = m.group(s.g);
        const std::size_t  ci = s.c[k].index;
        const double      *st = s.state(k);
        const ContactForce f  = G.local_force[ci];
        const Vec<dim>     n  = G.force[ci].normalized(); // F = -Fn n, Fn < 0: along +n
        INFO("contact " << k);
        // A compressive force develops (Fn < 0 is compression).
        CHECK(f.Fn < 0);
        fn_phase1[k] = f.Fn;
        // Contact normal from centre (piece 1) to neighbour.
        const Vec<dim> n_c = (m.particles.x[G.end2[ci]] - m.particles.x[G.end1[ci]]).normalized();
        CHECK((n - n_c).norm() < 1e-12); // frictionless: the force is purely normal
        // Only the elements at the far end of the face carry load: those
        // whose surface point on the central grain moves INTO the neighbour
        // under a CCW spin (velocity omega k x r has a positive n component).
        int loaded = 0;
        for (int e = 0; e < nelements; ++e)
          {
            const auto rc  = FJ::element_centroid(p, st, e);
            Vec<dim>   pos = G.xc[ci];
            if constexpr (dim == 2)
              pos += rc[1] * Vec<2>(-n_c[1], n_c[0]); // t = k x n
            else
              {
                const Vec<3> sa = G.s_axis[ci], ta = n_c.cross(sa);
                pos += rc[0] * sa + rc[1] * ta;
              }
            const Vec<dim> rel  = pos - m.particles.x[0];
            const double   vn   = omega * (-rel[1] * n_c[0] + rel[0] * n_c[1]); // (k x r).n
            const double   gap  = FJ::element_gap(p, st, e);
            const double   fn_e = FJ::element_force(p, p.prepared(), st, e)[0];
            const int      bs   = FJ::bond_state(p, st, e);
            CHECK(bs == 0);
            if (vn > 0)
              {
                ++loaded;
                CHECK(gap < 0);
                CHECK(fn_e < 0);
                // element gap = centroid arm along the spin-normal direction
                // times theta (memo Eq. 14/21): |g| = |vn| / omega * theta
                CHECK(gap == Approx(-vn / omega * theta).epsilon(1e-9));
              }
            else
              {
                CHECK(gap > 0);
                CHECK(fn_e == 0.0);
              }
          }
        CHECK(loaded == nelements / 2);
        // Magnitude of the face moment about z on the centre: the scatter
        // applies -(M + r1 x F) and r1 is parallel to F here.
        const double mz_centre = -z_of<dim>(G.moment[ci]);
        CHECK(mz_centre == Approx(Mface).epsilon(1e-9));
        if constexpr (dim == 2)
          {
            // resultant normal force of the closed half: kn theta R^2 / 2
            CHECK(f.Fn == Approx(-p.kn * theta * R * R / 2).epsilon(1e-9));
          }
      }
    // The four contacts resist the imposed CCW rotation.
    const double mz = z_of<dim>(m.particles.m[0]);
    CHECK(mz < 0);
    CHECK(mz == Approx(4 * Mface).epsilon(1e-3));
    if constexpr (dim == 2)
      CHECK(mz == Approx(-4.0 / 3.0 * p.kn * theta * R * R * R).epsilon(1e-9));
    else
      {
        // The element scheme is below the continuum half-disk value
        // kn theta pi R^4 / 8 (memo §2.1.3: converges from below).
        const double cont = -4 * p.kn * theta * M_PI * std::pow(R, 4) / 8;
        CHECK(std::abs(mz) < std::abs(cont));
        CHECK(std::abs(mz) > 0.5 * std::abs(cont));
        CHECK(m.particles.m[0][0] == Approx(0).margin(1e-9 * std::abs(mz)));
        CHECK(m.particles.m[0][1] == Approx(0).margin(1e-9 * std::abs(mz)));
      }
    WARN("dim " << dim << " phase 1: moment on centre " << mz << " N m, closed form " << 4 * Mface);

    // ---- phase 2: stop the centre, free the rotation of the others -------
    m.particles.w[0].setZero();
    for (std::size_t i = 1; i <= 4; ++i)
      m.particles.fixity[i] = fix_translation;
    double rot[5]       = {0, 0, 0, 0, 0};
    bool   first_ccw[5] = {false, false, false, false, false};
    for (int step = 0; step < 4000; ++step)
      {
        m.step();
        for (int i = 1; i <= 4; ++i)
          {
            rot[i] += z_of<dim>(m.particles.w[i]) * s.dt;
            if (step == 0)
              first_ccw[i] = z_of<dim>(m.particles.w[i]) > 0;
          }
      }
    for (int k = 0; k < 4; ++k)
      {
        const int          i = k + 1;
        const auto        &G = m.group(s.g);
        const ContactForce f = G.local_force[s.c[k].index];
        INFO("grain " << i << " rotation " << rot[i] << " Fn " << f.Fn << " (phase 1 "
                      << fn_phase1[k] << ")");
        // The compression at the far end of the face pushes the neighbour
        // along +n at a point on the CCW-leading side: its moment about the
        // neighbour's centre is counter-clockwise, so the neighbours turn
        // CCW, with the centre, until the relative bend vanishes (mu = 0:
        // no shear resistance, so equilibrium is zero interface stress).
        CHECK(first_ccw[i]);
        CHECK(rot[i] == Approx(theta).epsilon(1e-3));
        // Forces relax: the residual is below 1e-3 of the phase-1 force.
        CHECK(std::abs(f.Fn) < 1e-3 * std::abs(fn_phase1[k]));
        if constexpr (dim == 3)
          {
            CHECK(std::abs(m.particles.w[i][0]) < 1e-9);
            CHECK(std::abs(m.particles.w[i][1]) < 1e-9);
          }
        if (k == 0)
          WARN("dim " << dim << " phase 2: neighbour rotation " << rot[i] << " (theta " << theta
                      << "), Fn " << f.Fn << " vs phase 1 " << fn_phase1[k]);
      }
  }
} // namespace

TEST_CASE("interlocked grain 2D (memo §2.2, Fig. 24)", "[interlocked]") { run_interlocked<2>(); }

TEST_CASE("interlocked grain 3D (memo §2.2, Fig. 25)", "[interlocked]") { run_interlocked<3>(); }
