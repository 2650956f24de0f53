#include "dem/engine/law_registry.h"

#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/parallel_bond_law.h"
#include "dem/laws/smooth_joint_law.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace demfem::dem
{
  namespace
  {
    /// A property keyword and how it sets a field of P.
    template <class P>
    struct Key
    {
      const char                       *name;
      std::function<void(P &, double)> set;
    };

    template <class P>
    P parse(const std::vector<Key<P>> &keys, const LawProperties &props, const std::string &law,
            const std::string &where)
    {
      P p;
      for (const auto &[k, v] : props)
        {
          auto it = std::find_if(keys.begin(), keys.end(), [&](const Key<P> &x) { return k == x.name; });
          if (it == keys.end())
            {
              std::ostringstream msg;
              msg << where << ": unknown property '" << k << "' for contact law '" << law
                  << "'; allowed:";
              for (const auto &x : keys)
                msg << " " << x.name;
              throw InputError(msg.str());
            }
          it->set(p, v);
        }
      return p;
    }

    int as_int(double v) { return static_cast<int>(std::lround(v)); }

    /// Keys of the linear block; P is LinearLaw's Params or Props.
    template <int dim, class P = typename LinearLaw<dim>::Params>
    std::vector<Key<P>> keys_linear()
    {
      return {{"kn", [](P &p, double v) { p.kn = v; }},
              {"ks", [](P &p, double v) { p.ks = v; }},
              {"fric", [](P &p, double v) { p.friction = v; }},
              {"rgap", [](P &p, double v) { p.reference_gap = v; }}};
    }

    /// Linear keys lifted into a law whose Params has a `linear` member.
    template <int dim, class P>
    std::vector<Key<P>> lifted_linear()
    {
      std::vector<Key<P>> out;
      for (auto k : keys_linear<dim, typename LinearLaw<dim>::Props>())
        out.push_back({k.name, [set = k.set](P &p, double v) { set(p.linear, v); }});
      return out;
    }

    template <int dim>
    std::vector<Key<typename FlatJointLaw<dim>::Params>> keys_flatjoint()
    {
      using P = typename FlatJointLaw<dim>::Params;
      return {{"fj_Nr", [](P &p, double v) { p.Nr = as_int(v); }},
              {"fj_Nal", [](P &p, double v) { p.Nal = as_int(v); }},
              {"fj_rmul", [](P &p, double v) { p.rmul = v; }},
              {"fj_gap0", [](P &p, double v) { p.gap0 = v; }},
              {"fj_kn", [](P &p, double v) { p.kn = v; }},
              {"fj_ks", [](P &p, double v) { p.ks = v; }},
              {"fj_fric", [](P &p, double v) { p.fric = v; }},
              {"fj_ten", [](P &p, double v) { p.ten = v; }},
              {"fj_coh", [](P &p, double v) { p.coh = v; }},
              {"fj_fa", [](P &p, double v) { p.fa = v; }},
              {"fj_bonded", [](P &p, double v) { p.bonded = v != 0; }}};
    }

    template <int dim>
    std::vector<Key<typename ContactBondLaw<dim>::Params>> keys_contactbond()
    {
      using P = typename ContactBondLaw<dim>::Params;
      auto k  = lifted_linear<dim, P>();
      k.push_back({"cb_tenf", [](P &p, double v) { p.cb_tenf = v; }});
      k.push_back({"cb_shearf", [](P &p, double v) { p.cb_shearf = v; }});
      k.push_back({"cb_bonded", [](P &p, double v) { p.bonded = v != 0; }});
      return k;
    }

    template <int dim>
    std::vector<Key<typename ParallelBondLaw<dim>::Params>> keys_parallelbond()
    {
      using P = typename ParallelBondLaw<dim>::Params;
      auto k  = lifted_linear<dim, P>();
      k.push_back({"pb_kn", [](P &p, double v) { p.pb_kn = v; }});
      k.push_back({"pb_ks", [](P &p, double v) { p.pb_ks = v; }});
      k.push_back({"pb_rmul", [](P &p, double v) { p.pb_rmul = v; }});
      k.push_back({"pb_mcf", [](P &p, double v) { p.pb_mcf = v; }});
      k.push_back({"pb_ten", [](P &p, double v) { p.pb_ten = v; }});
      k.push_back({"pb_coh", [](P &p, double v) { p.pb_coh = v; }});
      k.push_back({"pb_fa", [](P &p, double v) { p.pb_fa = v; }});
      k.push_back({"pb_bonded", [](P &p, double v) { p.bonded = v != 0; }});
      return k;
    }

    template <int dim>
    std::vector<Key<typename SmoothJointLaw<dim>::Params>> keys_smoothjoint()
    {
      using P = typename SmoothJointLaw<dim>::Params;
      return {{"sj_kn", [](P &p, double v) { p.sj_kn = v; }},
              {"sj_ks", [](P &p, double v) { p.sj_ks = v; }},
              {"sj_fric", [](P &p, double v) { p.sj_fric = v; }},
              {"sj_da", [](P &p, double v) { p.sj_da = v; }},
              {"sj_ten", [](P &p, double v) { p.sj_ten = v; }},
              {"sj_coh", [](P &p, double v) { p.sj_coh = v; }},
              {"sj_fa", [](P &p, double v) { p.sj_fa = v; }},
              {"sj_rmul", [](P &p, double v) { p.sj_rmul = v; }},
              {"dip", [](P &p, double v) { p.dip = v; }},
              {"ddir", [](P &p, double v) { p.ddir = v; }},
              {"sj_large", [](P &p, double v) { p.sj_large = v != 0; }},
              {"sj_bonded", [](P &p, double v) { p.bonded = v != 0; }}};
    }

    template <class K>
    std::vector<std::string> names(const K &keys)
    {
      std::vector<std::string> n;
      for (const auto &k : keys)
        n.push_back(k.name);
      return n;
    }
  } // namespace

  const std::vector<LawInfo> &registered_laws()
  {
    static const std::vector<LawInfo> laws = {
      {LinearLaw<3>::name, "linear springs, no tension, Coulomb slip", names(keys_linear<3>())},
      {ContactBondLaw<3>::name, "linear + contact bond (force strengths)", names(keys_contactbond<3>())},
      {ParallelBondLaw<3>::name, "linear + parallel bond (memo §2.1.2)", names(keys_parallelbond<3>())},
      {FlatJointLaw<3>::name, "flat joint (memo §1.4-1.13)", names(keys_flatjoint<3>())},
      {SmoothJointLaw<3>::name, "smooth joint with dilation (seed 001)", names(keys_smoothjoint<3>())}};
    return laws;
  }

  template <int dim>
  int add_law_by_name(Model<dim> &model, const std::string &law, const LawProperties &props,
                      const std::string &where)
  {
    if (law == LinearLaw<dim>::name)
      return model.template add_law<LinearLaw<dim>>(parse(keys_linear<dim>(), props, law, where), where);
    if (law == ContactBondLaw<dim>::name)
      return model.template add_law<ContactBondLaw<dim>>(parse(keys_contactbond<dim>(), props, law, where), where);
    if (law == ParallelBondLaw<dim>::name)
      return model.template add_law<ParallelBondLaw<dim>>(parse(keys_parallelbond<dim>(), props, law, where), where);
    if (law == FlatJointLaw<dim>::name)
      return model.template add_law<FlatJointLaw<dim>>(parse(keys_flatjoint<dim>(), props, law, where), where);
    if (law == SmoothJointLaw<dim>::name)
      return model.template add_law<SmoothJointLaw<dim>>(parse(keys_smoothjoint<dim>(), props, law, where), where);
    std::ostringstream msg;
    msg << where << ": unknown contact law '" << law << "'; allowed:";
    for (const auto &l : registered_laws())
      msg << " " << l.name;
    throw InputError(msg.str());
  }

  template int add_law_by_name<2>(Model<2> &, const std::string &, const LawProperties &, const std::string &);
  template int add_law_by_name<3>(Model<3> &, const std::string &, const LawProperties &, const std::string &);
} // namespace demfem::dem
