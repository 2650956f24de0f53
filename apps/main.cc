// demfem: bonded-particle (flat-joint) rock embedded in a finite-element
// continuum. This file only dispatches to the subcommands.
#include "apps/commands.h"

#include <cstring>
#include <iostream>
#include <string>

namespace
{
  struct Subcommand
  {
    const char *name;
    int (*run)(int, char **);
    const char *summary;
  };

  const Subcommand subcommands[] = {
    {"contact-test",
     demfem::apps::run_contact_test,
     "two-grain flat-joint / parallel-bond test (flat-joint memo 2.1)"},
    {"calibrate",
     demfem::apps::run_calibrate,
     "material genesis + lab tests -> material.json"},
    {"fem", demfem::apps::run_fem, "continuum-only run (e.g. Kirsch hole)"},
    {"tunnel", demfem::apps::run_tunnel, "coupled DEM-continuum tunnel excavation run"},
    {"bench", demfem::apps::run_bench, "performance benchmarks"},
    {"study", demfem::apps::run_study, "speed-versus-accuracy sweep and stability map"},
  };

  void print_help()
  {
    std::cout << "usage: demfem <subcommand> [options]\n"
                 "       demfem <subcommand> --help\n\nsubcommands:\n";
    for (const auto &s : subcommands)
      std::cout << "  " << s.name << std::string(14 - std::strlen(s.name), ' ')
                << s.summary << "\n";
  }
} // namespace

int main(int argc, char **argv)
{
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 ||
      std::strcmp(argv[1], "-h") == 0)
    {
      print_help();
      return argc < 2 ? 1 : 0;
    }
  if (std::strcmp(argv[1], "--list") == 0)
    {
      for (const auto &s : subcommands)
        std::cout << s.name << "\n";
      return 0;
    }
  for (const auto &s : subcommands)
    if (std::strcmp(argv[1], s.name) == 0)
      return s.run(argc - 1, argv + 1);
  std::cerr << "demfem: unknown subcommand '" << argv[1]
            << "' (run `demfem --help` for the list)\n";
  return 2;
}
