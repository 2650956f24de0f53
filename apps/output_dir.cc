#include "apps/output_dir.h"

#include <deal.II/base/mpi.h>

#include "apps/cli.h"
#include "apps/prm_cli.h"
#include "dem/io/vtk_output.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#ifndef DEMFEM_GIT_DESCRIBE
#define DEMFEM_GIT_DESCRIBE ""
#endif

namespace demfem::apps
{
  namespace fs = std::filesystem;
  using json   = nlohmann::json;

  namespace
  {
    std::string utc_now()
    {
      const std::time_t t = std::time(nullptr);
      std::tm           tm{};
      gmtime_r(&t, &tm);
      char buf[32];
      std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
      return buf;
    }

    std::string host_name()
    {
      char buf[256] = {};
      return ::gethostname(buf, sizeof buf - 1) == 0 ? buf : "unknown";
    }

    std::string read_text(const std::string &file)
    {
      std::ifstream     in(file);
      std::stringstream s;
      s << in.rdbuf();
      return s.str();
    }

    /// "pid P on host H since T (command C)" of a lock's text.
    std::string holder(const json &lock)
    {
      std::ostringstream s;
      s << "pid " << lock.value("pid", -1) << " on host " << lock.value("host", "?")
        << " since " << lock.value("start_time", "?") << " ("
        << lock.value("command_line", "?") << ")";
      return s.str();
    }

    /// A lock is stale when its process is gone: on this host only (another
    /// host's process table cannot be seen).
    bool stale(const json &lock)
    {
      if (lock.value("host", "") != host_name())
        return false;
      const long pid = lock.value("pid", -1L);
      return pid <= 0 || (::kill(pid_t(pid), 0) != 0 && errno == ESRCH);
    }
  } // namespace

  bool is_run_result(const std::string &name, bool directory)
  {
    // What the tunnel, study, fem and calibrate commands write (docs/tunnel.md).
    static const std::regex files(
        "(manifest|summary|material|fit)\\.json|log\\.txt|study\\.md|"
        ".*\\.(csv|svg|pvd|vtu|vtp|pvtu|h5)(\\.prev|\\.tmp)?");
    static const std::regex dirs("run_[0-9]+|reference_[0-9]+|vtk");
    return std::regex_match(name, directory ? dirs : files);
  }

  RunDirectory::RunDirectory(const std::string              &directory,
                             const dealii::ParameterHandler &prm, bool continuing)
      : directory_(directory)
      , lock_file_(directory + "/demfem.lock")
  {
    const CommandLine &cl = command_line();
    std::error_code    ec;
    created_ = !fs::exists(directory_);
    fs::create_directories(directory_, ec);
    if (ec || !fs::is_directory(directory_))
      throw UsageError("output directory '" + directory_ + "' cannot be created: " +
                       (ec ? ec.message() : std::string("not a directory")));

    std::vector<std::string> args = {"demfem", cl.command};
    args.insert(args.end(), cl.arguments.begin(), cl.arguments.end());
    const std::string command_text = shell_quoted(args);

    // The lock: O_EXCL makes one of two simultaneous runs the owner.
    const json lock = {{"pid", long(::getpid())},
                       {"host", host_name()},
                       {"start_time", utc_now()},
                       {"command_line", command_text}};
    lock_text_      = lock.dump(2) + "\n";
    for (int attempt = 0;; ++attempt)
      {
        const int fd = ::open(lock_file_.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
        if (fd >= 0)
          {
            const bool ok = ::write(fd, lock_text_.data(), lock_text_.size()) ==
                            ssize_t(lock_text_.size());
            ::close(fd);
            if (!ok)
              {
                ::unlink(lock_file_.c_str());
                throw UsageError("output directory '" + directory_ +
                                 "': cannot write the lock file " + lock_file_ +
                                 " (disk full?)");
              }
            break;
          }
        if (errno != EEXIST)
          throw UsageError("output directory '" + directory_ +
                           "': cannot create the lock file " + lock_file_ + ": " +
                           std::strerror(errno));
        json other;
        try
          {
            other = json::parse(read_text(lock_file_));
          }
        catch (const json::exception &)
          {
            // Being written this instant, or damaged: look again shortly.
            if (attempt < 20)
              {
                ::usleep(50000);
                continue;
              }
            throw UsageError("output directory '" + directory_ + "': the lock file " +
                             lock_file_ +
                             " is unreadable; if no run uses this directory, delete it");
          }
        if (!stale(other) || attempt >= 20)
          throw UsageError("output directory '" + directory_ +
                           "' is in use by another demfem run: " + holder(other) +
                           "; lock file " + lock_file_ +
                           ". Wait for that run, or choose another Problem/output "
                           "directory");
        // Stale: move it aside under a unique name, so that of two runs taking
        // it over at once only one removes it; then try again. Had another
        // run replaced it by its own lock meanwhile, that lock is put back.
        const std::string aside = lock_file_ + ".stale." + std::to_string(::getpid());
        if (::rename(lock_file_.c_str(), aside.c_str()) == 0)
          {
            if (json::parse(read_text(aside), nullptr, false) != other)
              {
                // Fails if another run took the name meanwhile: then its
                // lock stands, which is what we want.
                [[maybe_unused]] const int relinked =
                    ::link(aside.c_str(), lock_file_.c_str());
              }
            else
              std::fprintf(stderr,
                           "demfem: taking over the stale lock of %s (that process "
                           "is gone)\n",
                           holder(other).c_str());
            ::unlink(aside.c_str());
          }
      }

    try
      {
        std::vector<fs::path> results;
        for (const auto &e : fs::directory_iterator(directory_))
          if (is_run_result(e.path().filename().string(), e.is_directory()))
            results.push_back(e.path());
        if (!results.empty() && !continuing)
          {
            if (!cl.overwrite)
              throw UsageError(
                  "output directory '" + directory_ +
                  "' holds the results of an earlier run (e.g. " +
                  results.front().filename().string() +
                  "); pass --overwrite to delete them and run again, or choose another "
                  "Problem/output directory (--set \"Problem/output directory=...\")");
            for (const auto &r : results)
              fs::remove_all(r);
          }

        std::string version = DEMFEM_GIT_DESCRIBE;
        manifest_           = {{"command", cl.command},
                               {"command_line", command_text},
                               {"arguments", cl.arguments},
                               {"working_directory", fs::current_path().string()},
                               {"parameter_file", cl.file},
                               {"demfem_version", version.empty() ? "unknown" : version},
                               {"host", host_name()},
                               {"pid", long(::getpid())},
                               {"start_time", utc_now()},
                               {"end_time", nullptr},
                               {"status", "running"},
                               {"exit_code", nullptr},
                               {"overwrite", cl.overwrite},
                               {"continued", continuing && !results.empty()},
                               {"resolved", json::object()}};
        std::ostringstream p;
        prm.print_parameters(p, dealii::ParameterHandler::ShortJSON);
        try
          {
            manifest_["parameters"] = json::parse(p.str());
          }
        catch (const json::exception &)
          {
            manifest_["parameters"] = p.str();
          }
        write_manifest();
      }
    catch (...)
      {
        ::unlink(lock_file_.c_str());
        throw;
      }
  }

  RunDirectory::~RunDirectory()
  {
    // Without finish(): an exception left the command ("aborted"), or the
    // command does not report its status (then its end is all we know).
    if (!finished_)
      try
        {
          if (std::uncaught_exceptions() > 0)
            finish("aborted", 1);
          else
            {
              finished_             = true;
              manifest_["status"]   = "ended";
              manifest_["end_time"] = utc_now();
              write_manifest();
            }
        }
      catch (...)
        {
        }
    // Only our own lock: a lock we lost (deleted by hand and taken by
    // another run) is not ours to remove.
    if (read_text(lock_file_) != lock_text_)
      return;
    ::unlink(lock_file_.c_str());
    const json &code = manifest_["exit_code"];
    if (created_ && code.is_number_integer() && code.get<int>() != 0)
      {
        std::error_code ec;
        for (const auto &e : fs::directory_iterator(directory_, ec))
          if (e.path().filename() != "manifest.json")
            return; // the run wrote something: keep it with its manifest
        fs::remove(directory_ + "/manifest.json", ec);
        fs::remove(directory_, ec);
      }
  }

  void RunDirectory::resolved(const std::string &key, const json &value)
  {
    manifest_["resolved"][key] = value;
    write_manifest();
  }

  void RunDirectory::finish(const std::string &status, int exit_code)
  {
    finished_              = true;
    manifest_["status"]    = status;
    manifest_["exit_code"] = exit_code;
    manifest_["end_time"]  = utc_now();
    try
      {
        write_manifest();
      }
    catch (const std::exception &e)
      {
        // E.g. the disk is full: the run's own error (if any) has been
        // reported already and stays the one message; a successful run
        // says that its manifest still reads "running".
        if (status.rfind("error", 0) != 0)
          std::fprintf(stderr, "demfem: warning: %s/manifest.json not updated: %s\n",
                       directory_.c_str(), e.what());
      }
  }

  void RunDirectory::write_manifest() const
  {
    dem::vtkout::write_text_atomically(directory_ + "/manifest.json",
                                       manifest_.dump(2) + "\n");
  }

  void claim_output_directory(std::optional<RunDirectory>    &slot,
                              const std::string              &directory,
                              const dealii::ParameterHandler &prm, bool continuing)
  {
    namespace mpi           = dealii::Utilities::MPI;
    const bool  initialized = mpi::job_supports_mpi();
    std::string error;
    if (!initialized || mpi::this_mpi_process(MPI_COMM_WORLD) == 0)
      try
        {
          slot.emplace(directory, prm, continuing);
        }
      catch (const std::exception &e)
        {
          error = e.what();
        }
    if (initialized && mpi::n_mpi_processes(MPI_COMM_WORLD) > 1)
      error = mpi::broadcast(MPI_COMM_WORLD, error, 0);
    if (!error.empty())
      throw UsageError(error);
  }
} // namespace demfem::apps
