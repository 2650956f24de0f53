#pragma once
// A run owns its output directory (docs/tunnel.md, "Output directory: lock,
// manifest, --overwrite"):
// - a lock file `demfem.lock` (pid, host, start time, command) refuses a
//   second run into the same directory while the first is alive; a lock
//   whose process is dead (same host) is stale and taken over;
// - a directory that holds an earlier run's results is refused unless
//   --overwrite, which first deletes those results (and only those);
// - `manifest.json` records the command line, the parameters as resolved,
//   the demfem version, the start time and, at the end, the status.
// Every file here is written through a temporary file in the same directory
// and a rename, so a kill leaves the previous complete file.
#include <deal.II/base/parameter_handler.h>

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace demfem::apps
{
  /// Claims a run's output directory for the lifetime of the object.
  class RunDirectory
  {
  public:
    /// Creates `directory` if needed, takes its lock, refuses (UsageError
    /// naming --overwrite) a directory with an earlier run's results unless
    /// the command line has --overwrite (then deletes them), and writes
    /// manifest.json with status "running". `prm` holds the parameters
    /// after the --set overrides. `continuing`: a restart from a checkpoint
    /// in this same directory continues its run, so the results are kept and
    /// no --overwrite is needed.
    RunDirectory(const std::string &directory, const dealii::ParameterHandler &prm,
                 bool continuing = false);
    /// Releases the lock; a run that did not call finish() is recorded as
    /// "aborted" when an exception left the command, else as "ended" (a
    /// command that does not report its status). A failed run that wrote
    /// nothing into a directory it created removes that directory again, so
    /// that bad input leaves nothing behind.
    ~RunDirectory();
    RunDirectory(const RunDirectory &)            = delete;
    RunDirectory &operator=(const RunDirectory &) = delete;

    /// Adds a value resolved at run time (e.g. 'DEM region/radius = auto')
    /// to the manifest's "resolved" object.
    void resolved(const std::string &key, const nlohmann::json &value);

    /// Records the end status ("ok", "diverged", "interrupted", "error: ...")
    /// and the exit code in the manifest. Never throws (it is called from
    /// error handlers): a manifest that cannot be written is a warning.
    void finish(const std::string &status, int exit_code);

    const std::string &path() const { return directory_; }

  private:
    void write_manifest() const;

    std::string    directory_;
    std::string    lock_file_;
    std::string    lock_text_;
    nlohmann::json manifest_;
    bool           finished_ = false;
    bool           created_  = false; ///< the directory did not exist before
  };

  /// Claims `directory` into `slot` on MPI rank 0 only (one owner per
  /// directory; every rank writes into it) and tells all ranks the outcome
  /// together: a rank alone in an error would leave the others waiting in a
  /// collective. Throws UsageError on every rank if the claim failed.
  void claim_output_directory(std::optional<RunDirectory>    &slot,
                              const std::string              &directory,
                              const dealii::ParameterHandler &prm,
                              bool                            continuing = false);

  /// Result files of demfem runs that --overwrite deletes from a directory
  /// (and whose presence marks it as used): a list of names and patterns.
  bool is_run_result(const std::string &name, bool directory);
} // namespace demfem::apps
