// The 3D flat-joint update has a fast path for contacts whose elements are
// all bonded and not slipping (update_bonded_elements_3d in dem/laws/flat_joint_elements.h, the state
// of intact material). It must give bitwise the results of the general
// element loop, and must hand over to it (having written nothing) when an
// element breaks. The general loop is forced here by marking element 0 as
// "bonded, was slipping" (code 3 + 4): for a bonded element the general loop
// then does the same arithmetic and only adds a slip_end event.
#include "dem/laws/flat_joint_law.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <vector>

using namespace demfem::dem;

namespace
{
  using Law = FlatJointLaw<3>;

  Law::Params params(int Nr, int Nal)
  {
    Law::Params p;
    p.Nr     = Nr;
    p.Nal    = Nal;
    p.rmul   = 0.8;
    p.kn     = 2.32e12; // memo §2.1 granite, L = 12.5 mm
    p.ks     = 1.0087e12;
    p.ten    = 1e7; // sigma_c, c [Pa]: an opening of 1e-5 m breaks in tension
    p.coh    = 1e7;
    p.fa     = 30; // tan(phi) != 0 enters the shear strength
    p.fric   = 0.5;
    p.bonded = true;
    p.validate("test");
    return p;
  }

  ContactStep<3> plane()
  {
    ContactStep<3> k;
    k.R1 = k.R2 = 6.25e-3;
    k.n         = Vec<3>(0, 1, 0);
    k.s         = Vec<3>(1, 0, 0);
    k.t         = Vec<3>(0, 0, -1);
    k.dt        = 1;
    return k;
  }

  /// Random increments of the size of a few explicit steps: stresses stay
  /// far below the strengths (kn * 1e-8 m = 2e4 Pa against 1e7 Pa).
  ContactStep<3> random_step(std::mt19937_64 &gen, double scale)
  {
    std::uniform_real_distribution<double> u(-1, 1);
    ContactStep<3>                         k = plane();
    k.d_n = scale * u(gen), k.d_ss = scale * u(gen), k.d_st = scale * u(gen);
    k.d_twist = 100 * scale * u(gen), k.d_bs = 100 * scale * u(gen);
    k.d_bt = 100 * scale * u(gen);
    return k;
  }

  bool same(const ContactForce &a, const ContactForce &b)
  {
    return a.Fn == b.Fn && a.Fss == b.Fss && a.Fst == b.Fst && a.Mt == b.Mt &&
           a.Mbs == b.Mbs && a.Mbt == b.Mbt;
  }

  int count(const EventSink &s, LawEvent::Kind kind)
  {
    int c = 0;
    for (const auto &e : s.events)
      c += e.second.kind == kind;
    return c;
  }
} // namespace

TEST_CASE("flatjoint 3D: the bonded fast path is bitwise the general loop", "[flatjoint]")
{
  std::mt19937_64 gen(42);
  // (2, 8) is the benchmark discretisation; (3, 4) another even count; with an
  // odd count (1, 3) only the general loop runs.
  for (auto [Nr, Nal] : {std::pair{2, 8}, std::pair{3, 4}, std::pair{1, 3}})
    {
      const Law::Params   p = params(Nr, Nal);
      std::vector<double> fast(Law::state_size(p));
      Law::install(p, p.prepared(), plane(), fast.data());
      EventSink sink_fast, sink_general;
      for (int step = 0; step < 200; ++step) // load the shear springs
        {
          ContactForce f;
          Law::update(p, p.prepared(), random_step(gen, 1e-8), fast.data(), f, sink_fast);
        }
      REQUIRE(sink_fast.events.empty());
      REQUIRE(Law::bonded_count(p, fast.data()) == Law::element_count(p));

      for (int trial = 0; trial < 50; ++trial)
        {
          std::vector<double> general        = fast;
          Law::code_array(general.data())[0] = Law::make_code(3, true);
          const ContactStep<3> k             = random_step(gen, 1e-8);
          ContactForce         f_fast, f_general;
          sink_fast.events.clear(), sink_general.events.clear();
          Law::update(p, p.prepared(), k, fast.data(), f_fast, sink_fast);
          Law::update(p, p.prepared(), k, general.data(), f_general, sink_general);
          CHECK(same(f_fast, f_general));
          CHECK(sink_fast.events.empty());
          CHECK(count(sink_general, LawEvent::slip_end) == 1);
          CHECK(fast == general); // every state double, codes included
        }

      // An opening of 1e-5 m (sigma = kn g ~ 2.3e7 Pa > sigma_c = 1e7 Pa)
      // breaks every element in tension: the fast path must hand over to
      // the general loop with the state untouched.
      std::vector<double> general        = fast;
      Law::code_array(general.data())[0] = Law::make_code(3, true);
      ContactStep<3> k                   = random_step(gen, 1e-8);
      k.d_n                              = 1e-5;
      ContactForce f_fast, f_general;
      sink_fast.events.clear(), sink_general.events.clear();
      Law::update(p, p.prepared(), k, fast.data(), f_fast, sink_fast);
      Law::update(p, p.prepared(), k, general.data(), f_general, sink_general);
      CHECK(same(f_fast, f_general));
      CHECK(f_fast.Fn == 0); // memo step 1: broken elements carry nothing
      CHECK(count(sink_fast, LawEvent::bond_break) == Law::element_count(p));
      CHECK(count(sink_general, LawEvent::bond_break) == Law::element_count(p));
      CHECK(Law::bonded_count(p, fast.data()) == 0);
      CHECK(fast == general);
    }
}

TEST_CASE("flatjoint 3D: element codes are bytes that survive a copy as doubles",
          "[flatjoint]")
{
  // The codes share the state block of doubles (one byte per element): a
  // contact block moved or checkpointed as doubles keeps them bit for bit.
  const Law::Params   p = params(2, 8);
  std::vector<double> st(Law::state_size(p));
  Law::install(p, p.prepared(), plane(), st.data());
  CHECK(Law::state_size(p) == 6 + 2 + 3 * 16); // header, 16 code bytes, 3 fields
  Law::unbond(p, st.data(), 5);
  Law::code_array(st.data())[9] = Law::make_code(2, true);
  std::vector<double> copy(st.size());
  for (std::size_t i = 0; i < st.size(); ++i)
    copy[i] = st[i];
  for (int e = 0; e < 16; ++e)
    {
      const int B = e == 5 ? 0 : e == 9 ? 2 : 3;
      CHECK(Law::bond_state(p, copy.data(), e) == B);
      CHECK(Law::slipping(p, copy.data(), e) == (e == 9));
    }
  CHECK(Law::bonded_count(p, copy.data()) == 14);
}
