// Kirsch solution of a circular hole (radius a) in an infinite plane-strain
// medium, far-field stress sxx = S1, syy = S2 (tension positive), released on
// the hole: excavation-induced displacement and stress, and the total stress.
#ifndef DEMFEM_TESTS_FEM_KIRSCH_H
#define DEMFEM_TESTS_FEM_KIRSCH_H

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/symmetric_tensor.h>

#include <cmath>

namespace demfem::test
{
  struct Kirsch
  {
    double a, S1, S2, E, nu;

    double shear_modulus() const { return E / (2 * (1 + nu)); }

    // Induced displacement (Jaeger & Cook form), Cartesian components.
    dealii::Tensor<1, 2> displacement(const double x, const double y) const
    {
      const double G = shear_modulus(), r = std::hypot(x, y), t = std::atan2(y, x);
      const double q  = a * a / (r * r);
      const double ur = a * a / (4 * G * r) *
                        ((S1 + S2) + (S1 - S2) * (4 * (1 - nu) - q) * std::cos(2 * t));
      const double ut =
          -a * a / (4 * G * r) * (S1 - S2) * (2 * (1 - 2 * nu) + q) * std::sin(2 * t);
      dealii::Tensor<1, 2> u;
      u[0] = ur * std::cos(t) - ut * std::sin(t);
      u[1] = ur * std::sin(t) + ut * std::cos(t);
      return u;
    }

    // Total stress (in-plane components).
    dealii::SymmetricTensor<2, 2> stress(const double x, const double y) const
    {
      const double r = std::hypot(x, y), t = std::atan2(y, x);
      const double q = a * a / (r * r), P = 0.5 * (S1 + S2), Q = 0.5 * (S1 - S2);
      const double srr = P * (1 - q) + Q * (1 - 4 * q + 3 * q * q) * std::cos(2 * t);
      const double stt = P * (1 + q) - Q * (1 + 3 * q * q) * std::cos(2 * t);
      const double srt = -Q * (1 + 2 * q - 3 * q * q) * std::sin(2 * t);
      const double c = std::cos(t), s = std::sin(t);
      dealii::SymmetricTensor<2, 2> sig;
      sig[0][0] = c * c * srr + s * s * stt - 2 * s * c * srt;
      sig[1][1] = s * s * srr + c * c * stt + 2 * s * c * srt;
      sig[0][1] = s * c * (srr - stt) + (c * c - s * s) * srt;
      return sig;
    }

    // Hoop stress on the wall at polar angle t.
    double wall_hoop_stress(const double t) const
    {
      return (S1 + S2) - 2 * (S1 - S2) * std::cos(2 * t);
    }
  };

  // Induced displacement as a deal.II function (dim components; u_z = 0).
  template <int dim>
  class KirschDisplacement : public dealii::Function<dim>
  {
  public:
    explicit KirschDisplacement(const Kirsch &k)
        : dealii::Function<dim>(dim)
        , k(k)
    {
    }
    double value(const dealii::Point<dim> &p, const unsigned int c) const override
    {
      return c < 2 ? k.displacement(p[0], p[1])[c] : 0.0;
    }

  private:
    Kirsch k;
  };

  // MPI for tests that build deal.II distributed objects; finalized at exit.
  inline void ensure_mpi()
  {
    static int                                      argc   = 1;
    static char                                     name[] = "test_fem";
    static char                                    *args[] = {name, nullptr};
    static char                                   **argv   = args;
    static dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  }
} // namespace demfem::test

#endif
