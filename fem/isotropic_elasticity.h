#pragma once
// Isotropic linear elasticity shared by the continuum solvers (ElasticProblem,
// ExplicitDynamics, StaticInterfaceResponse): Lame constants from (E, nu) and
// the cell stiffness integral, so the three assemble the same bilinear form.
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/lac/full_matrix.h>

#include <vector>

namespace demfem::fem
{
  struct LameConstants
  {
    double lambda = 0, mu = 0;
  };

  /// lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)); in 2D
  /// these are the plane-strain constants of (E, nu).
  inline LameConstants lame_constants(double E, double nu)
  {
    return {E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))};
  }

  /// Adds to cell_k the integral over the cell of fe_values of
  /// lambda tr(eps_i) tr(eps_j) + 2 mu eps_i : eps_j (displacement field in
  /// the first dim components). The lower triangle is integrated and
  /// mirrored (the form is symmetric; each entry is bitwise the full loop's).
  /// `eps` is scratch space (resized here).
  template <int dim>
  void add_isotropic_stiffness(const dealii::FEValues<dim>                  &fe_values,
                               const LameConstants                          &c,
                               std::vector<dealii::SymmetricTensor<2, dim>> &eps,
                               dealii::FullMatrix<double>                   &cell_k)
  {
    const dealii::FEValuesExtractors::Vector displacement(0);
    const unsigned int                       n = fe_values.dofs_per_cell;
    eps.resize(n);
    dealii::FullMatrix<double> lower(n, n);
    for (const unsigned int q : fe_values.quadrature_point_indices())
      {
        for (unsigned int i = 0; i < n; ++i)
          eps[i] = fe_values[displacement].symmetric_gradient(i, q);
        const double w = fe_values.JxW(q);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j <= i; ++j)
            lower(i, j) += (c.lambda * trace(eps[i]) * trace(eps[j]) +
                            2 * c.mu * (eps[i] * eps[j])) *
                           w;
      }
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        cell_k(i, j) += j <= i ? lower(i, j) : lower(j, i);
  }
} // namespace demfem::fem
