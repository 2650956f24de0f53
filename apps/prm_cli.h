#pragma once
// The command line shared by every subcommand that reads a .prm file:
//   demfem <cmd> FILE.prm [--set "Section/sub/key=value"]... [--print-parameters]
//   [--help]
#include <deal.II/base/parameter_handler.h>

#include <exception>
#include <string>

namespace demfem::apps
{
  /// What the command line asks for once the parameters are read.
  enum class PrmAction
  {
    run,  ///< run the subcommand with the parameters
    help, ///< print the usage and exit 0
    print ///< print every parameter with its default and doc, exit 0
  };

  /// Parses the command line, reads FILE.prm into `prm` (declared by the
  /// caller) and applies the `--set` overrides in order. Throws
  /// dealii::ExceptionBase (via AssertThrow) naming the option, the file or
  /// the key on any error; `file` receives the parameter file name.
  PrmAction read_parameters(int argc, char **argv, dealii::ParameterHandler &prm,
                            const std::string &usage, std::string &file);

  /// Sets "Section/sub/key=value" inside its subsections.
  void apply_override(dealii::ParameterHandler &prm, const std::string &arg);

  /// Declares, in the current subsection (Tunnel), the keys `in situ stress
  /// xx|yy|zz|xy|xz|yz` [Pa, tension positive] shared by fem and tunnel.
  void declare_in_situ_stress(dealii::ParameterHandler &prm);

  /// The message of an exception without deal.II's decoration.
  std::string exception_text(const std::exception &e);
} // namespace demfem::apps
