#pragma once
// Runs the built `demfem` executable and captures stdout, stderr, exit code.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace demfem::testing
{
  struct CommandResult
  {
    int         exit_code = -1;
    std::string out;
  };

  /// Runs `DEMFEM_EXE args` with stderr merged into the captured output.
  inline CommandResult run_demfem(const std::string &args)
  {
    CommandResult     r;
    const std::string cmd = std::string(DEMFEM_EXE) + " " + args + " 2>&1";
    FILE             *p   = popen(cmd.c_str(), "r");
    if (!p)
      return r;
    std::array<char, 4096> buf;
    while (fgets(buf.data(), buf.size(), p))
      r.out += buf.data();
    const int status = pclose(p);
    r.exit_code      = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
  }

  /// run_demfem(args) with OMP_NUM_THREADS = threads (restored after).
  inline CommandResult run_with_threads(const std::string &args, const int threads)
  {
    const char       *old   = std::getenv("OMP_NUM_THREADS");
    const std::string saved = old ? old : "";
    setenv("OMP_NUM_THREADS", std::to_string(threads).c_str(), 1);
    CommandResult r = run_demfem(args);
    if (old)
      setenv("OMP_NUM_THREADS", saved.c_str(), 1);
    else
      unsetenv("OMP_NUM_THREADS");
    return r;
  }

  /// `demfem study apps/examples/EXAMPLE` into output directory d with more
  /// --set options (DEMFEM_SOURCE_DIR: the test target's definition).
  inline CommandResult run_study(const std::string &example, const std::string &d,
                                 const std::string &sets)
  {
    return run_demfem("study " + std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/" +
                      example + " --set \"Problem/output directory=" + d + "\" " + sets);
  }

  /// Extracts the numeric fields of a flat JSON object.
  inline std::map<std::string, double> json_numbers(const std::string &text)
  {
    std::map<std::string, double> v;
    const std::regex              field("\"([A-Za-z_0-9]+)\"\\s*:\\s*(-?[0-9.eE+-]+)");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), field);
         it != std::sregex_iterator(); ++it)
      v[(*it)[1]] = std::stod((*it)[2]);
    return v;
  }
  /// The whole text of a file ("" when it cannot be read).
  inline std::string read_text(const std::string &file)
  {
    std::ifstream     in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
} // namespace demfem::testing
