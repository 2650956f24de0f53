// The registry maps PFC keywords to laws and rejects bad input clearly.
#include "dem/laws/flat_joint_law.h"
#include "dem/engine/law_registry.h"

#include <catch2/catch.hpp>

using namespace demfem::dem;

TEST_CASE("registry lists every law and builds it from keywords", "[registry]")
{
  std::vector<std::string> names;
  for (const auto &l : registered_laws())
    names.push_back(l.name);
  CHECK(names == std::vector<std::string>{"linear", "contactbond", "parallelbond", "flatjoint", "smoothjoint"});

  Model<3> m;
  const int g = add_law_by_name(m, "flatjoint", {{"fj_Nr", 3}, {"fj_Nal", 6}, {"fj_kn", 1e12}, {"fj_ks", 5e11}},
                                "test.prm");
  CHECK(std::string(m.group(g).law_name()) == "flatjoint");
  auto &grp = dynamic_cast<ContactGroup<3, FlatJointLaw<3>> &>(m.group(g));
  CHECK(grp.params.Nr == 3);
  CHECK(grp.params.Nal == 6);
  CHECK(grp.params.kn == 1e12);
}

TEST_CASE("registry errors name the file, law, key and range", "[registry]")
{
  Model<2> m;
  CHECK_THROWS_WITH(add_law_by_name(m, "hertz", {}, "a.prm"),
                    Catch::Contains("a.prm") && Catch::Contains("hertz") && Catch::Contains("flatjoint"));
  CHECK_THROWS_WITH(add_law_by_name(m, "flatjoint", {{"fj_kx", 1}}, "a.prm"),
                    Catch::Contains("fj_kx") && Catch::Contains("fj_kn"));
  CHECK_THROWS_WITH(add_law_by_name(m, "flatjoint", {{"fj_fa", 90}}, "a.prm"),
                    Catch::Contains("a.prm") && Catch::Contains("fa") && Catch::Contains("90"));
  CHECK_THROWS_AS(add_law_by_name(m, "smoothjoint", {{"sj_kn", -1}}, "a.prm"), InputError);
  CHECK_THROWS_AS(add_law_by_name(m, "parallelbond", {{"pb_mcf", 2}}, "a.prm"), InputError);
}
