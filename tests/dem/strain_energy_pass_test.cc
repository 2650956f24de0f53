// Model::step evaluates the strain energy of the energy-balance check inside
// the force pass (ContactGroupBase::request_strain_energy), while each state
// block is in cache. The group total must then be the energy of the current
// state: equal to the per-contact sum after the step, and recomputed, not
// taken from the pass, once a state has been changed by hand.
#include "dem/laws/flat_joint_law.h"
#include "dem/engine/model.h"

#include <catch2/catch.hpp>
#include <omp.h>

using namespace demfem::dem;

namespace
{
  struct OneThread
  {
    int old = omp_get_max_threads();
    OneThread() { omp_set_num_threads(1); }
    ~OneThread() { omp_set_num_threads(old); }
  };

  double sum_of_contacts(const ContactGroupBase<3> &g)
  {
    double e = 0;
    for (std::size_t k = 0; k < g.size(); ++k)
      e += g.strain_energy(k);
    return e;
  }
} // namespace

TEST_CASE("strain energy from the force pass is that of the current state", "[engine]")
{
  OneThread    one;
  Model<3>     m;
  const double r = 0.01;
  // A bonded column of three grains pulled apart and sheared by the end grains.
  for (int i = 0; i < 3; ++i)
    m.particles.add(Vec<3>(0, 0, 2 * r * i), r, 2650);
  FlatJointLaw<3>::Params p;
  p.Nr = 2, p.Nal = 8, p.rmul = 1, p.kn = 1e11, p.ks = 4e10;
  p.ten = p.coh = 1e12, p.fa = 0, p.bonded = true;
  const int g = m.add_law<FlatJointLaw<3>>(p);
  m.install(0, 1, g);
  m.install(1, 2, g);
  m.particles.fixity[0] = m.particles.fixity[2] = fix_all;
  m.particles.v[2] = Vec<3>(0.01, 0.005, 0.02); // opening, sheared
  m.set_timestep(1e-7);
  m.cycle(10); // step 10 is an energy-check step: the pass evaluated it
  const auto  &G  = m.group(g);
  const double e1 = G.total_strain_energy();
  CHECK(e1 > 0);
  CHECK(e1 == sum_of_contacts(G)); // same function of the same state

  // Unbonding by hand (non-const state access) changes the energy: the
  // total must follow (the unbonded elements in tension carry nothing).
  FlatJointLaw<3>::unbond(p, m.group(g).state(1));
  const double e2 = G.total_strain_energy();
  CHECK(e2 == sum_of_contacts(G));
  CHECK(e2 != e1);
}
