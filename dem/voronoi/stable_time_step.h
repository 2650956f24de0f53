#pragma once
// The time step of a Voronoi-grain run in which contacts form (seed 004 §2,
// large displacements; docs/voronoi.md, "New contacts"). The models'
// stable_time_step() bounds the springs of the contacts present; a contact
// that forms later adds springs to its grains (rigid grains: to the sums
// per grain), so the step is derived again over all contacts after
// contacts have formed, and only ever lowered (a run does not speed up
// because a fragment flew off). Works with RigidVoronoiModel and
// FlexibleVoronoiModel.
#include <algorithm>

namespace demfem::dem::voronoi
{
  template <class Model>
  class StableTimeStep
  {
  public:
    StableTimeStep(const Model &model, double safety)
        : safety(safety)
        , contacts_bounded(model.contacts.n_contacts())
        , dt(model.stable_time_step(safety))
    {
    }

    /// The step to take [s].
    double value() const { return dt; }

    /// After a step: derives the step again if contacts have formed since
    /// it was derived. Returns true if it was lowered. O(1) otherwise.
    bool update(const Model &model)
    {
      if (model.contacts.n_contacts() == contacts_bounded)
        return false;
      contacts_bounded    = model.contacts.n_contacts();
      const double before = dt;
      dt                  = std::min(dt, model.stable_time_step(safety));
      return dt < before;
    }

  private:
    double safety;
    int    contacts_bounded;
    double dt;
  };
} // namespace demfem::dem::voronoi
