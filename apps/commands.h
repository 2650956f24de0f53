#pragma once
// Subcommands of the `demfem` executable. Each receives argv with argv[0]
// set to the subcommand name and returns the process exit code.
namespace demfem::apps
{
  int run_contact_test(int argc, char **argv);
  int run_bench(int argc, char **argv);
  int run_fem(int argc, char **argv);
  int run_tunnel(int argc, char **argv);
  int run_calibrate(int argc, char **argv);
  int run_study(int argc, char **argv);
} // namespace demfem::apps
