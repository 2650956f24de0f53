#pragma once
// The command line shared by every subcommand that reads a .prm file:
//   demfem <cmd> FILE.prm [--set "Section/sub/key=value"]... [--defaults]
//   [--overwrite] [--print-parameters] [--help]
#include <deal.II/base/parameter_handler.h>

#include <exception>
#include <ostream>
#include <string>
#include <vector>

namespace demfem::apps
{
  /// What the command line asks for once the parameters are read.
  enum class PrmAction
  {
    run,  ///< run the subcommand with the parameters
    help, ///< print the usage and exit 0
    print ///< print every parameter with its default and doc, exit 0
  };

  /// The command line as read_parameters saw it (one per process: a
  /// subcommand reads one parameter file).
  struct CommandLine
  {
    std::string              command;           ///< the subcommand, e.g. "tunnel"
    std::string              file;              ///< the .prm file ("" with --defaults)
    std::vector<std::string> overrides;         ///< the --set arguments, in order
    bool                     defaults  = false; ///< --defaults: a key-less file is fine
    bool                     overwrite = false; ///< --overwrite: replace old results
    std::vector<std::string> arguments;         ///< every argument after the subcommand
  };

  /// Options every .prm subcommand accepts, for its --help text.
  extern const char *common_options_help;

  /// Parses the command line, reads FILE.prm into `prm` (declared by the
  /// caller) and applies the `--set` overrides in order. Throws
  /// dealii::ExceptionBase (via AssertThrow) naming the option, the file or
  /// the key on any error: a directory, a missing file, a file that sets no
  /// key (unless --defaults), an unknown section or key in --set. `file`
  /// receives the parameter file name.
  PrmAction read_parameters(int argc, char **argv, dealii::ParameterHandler &prm,
                            const std::string &usage, std::string &file);

  /// Answers --help (usage and the common options) and --print-parameters
  /// (every key with its default and doc) on `out` when `out` is given
  /// (MPI: rank 0 only). Returns true when the command is answered and
  /// should exit 0, false when it should run.
  bool answered(PrmAction action, const dealii::ParameterHandler &prm,
                const std::string &usage, std::ostream *out);

  /// The command line of the last read_parameters call.
  const CommandLine &command_line();

  /// "Section/key (parameter file 'x.prm')" or "Section/key (--set)": how
  /// error messages name a key, with where its value came from.
  std::string key_name(const std::string &key_path);

  /// An input file named in the parameters (e.g. a material file): a
  /// relative path is taken from the current directory when it exists
  /// there, else from the parameter file's directory (so that an example
  /// names the files next to it and runs from anywhere). Returns the path
  /// to use (unchanged when neither exists: the caller's check names it).
  std::string resolve_input_file(const std::string &path);

  /// The arguments quoted for a POSIX shell, joined by blanks.
  std::string shell_quoted(const std::vector<std::string> &arguments);

  /// Sets "Section/sub/key=value" inside its subsections; an unknown
  /// section or key is an error naming it.
  void apply_override(dealii::ParameterHandler &prm, const std::string &arg);

  /// Declares, in the current subsection (Tunnel), the keys `in situ stress
  /// xx|yy|zz|xy|xz|yz` [Pa, tension positive] shared by fem and tunnel.
  void declare_in_situ_stress(dealii::ParameterHandler &prm);

  /// The message of an exception without deal.II's decoration.
  std::string exception_text(const std::exception &e);
} // namespace demfem::apps
