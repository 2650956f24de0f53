#pragma once
#include <deal.II/base/mpi.h>

#include "coupling/coupled_model.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace demfem::test
{
  // MPI for the deal.II distributed objects of the coupled model; finalized
  // at exit.
  inline void ensure_mpi_coupling()
  {
    static int                                      argc   = 1;
    static char                                     name[] = "test_coupling";
    static char                                    *args[] = {name, nullptr};
    static char                                   **argv   = args;
    static dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  }

  // The small verification region of the coupling tests (about 340
  // grains): radius 1 m, grains 8-12 cm, E* = 20 GPa. `grain_scale` < 1
  // makes the grains finer: the patch tests (patch_test.cc,
  // quasi_static_test.cc) use 0.5 (4-6 cm, about 1 400 grains), because
  // at 8-12 cm the fabric of the random packing made the region stress
  // anisotropic by up to 8 % between x and y (deviators 0.11-0.34 MPa at
  // 10 MPa over packing seeds).
  inline coupling::RegionParams small_region(bool   breakable   = false,
                                             double grain_scale = 1)
  {
    coupling::RegionParams r;
    r.radius    = 1.0;
    r.d_lo      = 0.08 * grain_scale;
    r.d_hi      = 0.12 * grain_scale;
    r.emod      = 20e9;
    r.lnm_emod  = 20e9;
    r.breakable = breakable;
    return r;
  }

  // In-situ installation in model time (coupling/coupled_model.h): the
  // load factor rises over t_ramp with the grains held on the affine path,
  // then the model cycles until the grains' and the continuum's unbalanced
  // ratios and the interface residual are all below `tol` (checked every
  // t_ramp / 20), or to t_limit. Physical times, so that neither the grain
  // size nor the time step sets the load path. Returns whether it settled.
  template <int dim>
  bool install_insitu(coupling::CoupledModel<dim> &m, double t_ramp, double t_limit,
                      double tol = 1e-4)
  {
    const double t_check = t_ramp / 20;
    while (m.dem.time() < t_ramp)
      {
        m.set_load_factor(std::min(1.0, m.dem.time() / t_ramp));
        m.step();
      }
    m.set_load_factor(1.0);
    for (double next = m.dem.time() + t_check; m.dem.time() < t_limit;)
      {
        m.step();
        if (m.dem.time() < next)
          continue;
        next += t_check;
        if (!m.installing() && m.dem.unbalanced_ratio() < tol &&
            m.continuum_unbalanced_ratio() < tol && m.interface_residual() < tol)
          return true;
      }
    return false;
  }

  // Plane-strain continuum to R = 10 m around it.
  inline coupling::ContinuumParams continuum(double E, double nu)
  {
    coupling::ContinuumParams c;
    c.young_modulus = E;
    c.poisson_ratio = nu;
    c.outer_radius  = 10;
    return c;
  }
  // Excavation convergence of a 3D coupled region against Kirsch: the
  // least-squares fit u_r = C / r (Kirsch: C = -p a^2 / (2 G)) over the
  // grains between two mean diameters d from the wall r = a and two from the
  // continuum's inner radius b_free whose reference z lies in (z0, z1), and
  // the mean u_r r / a (Kirsch: -p a / (2 G)) of the grains within one
  // diameter of the wall. `ref`: grain positions by id before excavation.
  struct KirschFit
  {
    double C = 0, wall = 0;
    int    n_wall = 0;
  };
  inline KirschFit kirsch_fit(const dem::Particles<3>        &P,
                              const std::vector<dem::Vec<3>> &ref, double a, double d,
                              double b_free, double z0 = -HUGE_VAL, double z1 = HUGE_VAL)
  {
    KirschFit f;
    double    sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      {
        const dem::Vec<2> X  = ref[P.id[i]].head<2>();
        const double      r  = X.norm();
        const double      ur = (P.x[i].head<2>() - X).dot(X / r);
        const double      z  = ref[P.id[i]][2];
        if (r < a + d)
          {
            f.wall += ur * r / a;
            ++f.n_wall;
          }
        if (r > a + 2 * d && r < b_free - 2 * d && z > z0 && z < z1)
          {
            sxy += ur / r;
            sxx += 1 / (r * r);
          }
      }
    f.wall /= f.n_wall;
    f.C = sxy / sxx;
    return f;
  }
  // A 3D slab or section of spheres (unbreakable, E* = 20 GPa): radius b,
  // grains d_lo .. d_hi, thickness t (0 < z < t).
  inline coupling::RegionParams slab_region(double b, double d_lo, double d_hi, double t)
  {
    coupling::RegionParams r;
    r.radius         = b;
    r.d_lo           = d_lo;
    r.d_hi           = d_hi;
    r.emod           = 20e9;
    r.lnm_emod       = 20e9;
    r.breakable      = false;
    r.slab_thickness = t;
    return r;
  }

  inline std::string read_file(const std::string &f)
  {
    std::ifstream     in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

#if defined(DEMFEM_EXE) && defined(DEMFEM_SOURCE_DIR)
  // Runs `demfem tunnel apps/examples/PRM` into a fresh `dir` (a temporary
  // directory's entry) with the given --set options; output to dir + ".log".
  // Returns the status of std::system.
  inline int run_tunnel_example(const std::string &prm, const std::string &dir,
                                const std::string &sets)
  {
    std::filesystem::remove_all(dir);
    const std::string cmd = std::string(DEMFEM_EXE) + " tunnel " + DEMFEM_SOURCE_DIR +
                            "/apps/examples/" + prm +
                            " --set \"Problem/output directory=" + dir + "\" " + sets +
                            " > " + dir + ".log 2>&1";
    return std::system(cmd.c_str());
  }

  // tests/coupling/vtk_check_3d.py on a 3D run's output (slab thickness t,
  // axial extension L); output to dir + ".log.vtk". Returns the status.
  inline int check_vtk_3d(const std::string &dir, const std::string &t,
                          const std::string &L = "0")
  {
    const std::string cmd = "/usr/bin/python3 " + std::string(DEMFEM_SOURCE_DIR) +
                            "/tests/coupling/vtk_check_3d.py " + dir + " " + t + " " + L +
                            " > " + dir + ".log.vtk 2>&1";
    return std::system(cmd.c_str());
  }
#endif
} // namespace demfem::test
