// `demfem tunnel` stop / restart through the executable (docs/tunnel.md,
// "Checkpoints and restart"): the printed restart command repeats the whole
// command line (every --set), a restart into a new directory writes complete
// files there (history.csv with its header), a re-run into the used
// directory needs --overwrite, and a damaged checkpoint is refused naming the
// dataset and the file before anything is built.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace
{
  std::string read(const std::string &f)
  {
    std::ifstream     in(f, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  struct Run
  {
    int         code = -1;
    std::string text;
  };

  Run shell(const std::string &command, const std::string &log)
  {
    const int status = std::system((command + " > " + log + " 2>&1").c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read(log)};
  }
} // namespace

TEST_CASE("tunnel restart: the hint repeats the command line, a new directory gets "
          "complete files, a damaged checkpoint is refused",
          "[coupling][restart][app]")
{
  const std::string tmp =
      fs::temp_directory_path() / ("demfem_restart_cli_" + std::to_string(getpid()));
  const std::string dir = tmp + "/first", moved = tmp + "/moved", log = tmp + ".log";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const std::string prm = std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/tunnel_2d.prm";
  std::vector<std::string> args = {
      DEMFEM_EXE, "tunnel", prm, "--set", "DEM region/radius=1.0", "--set",
      "Tunnel/radius=0.4", "--set", "DEM region/grain diameter=0.1", "--set",
      "DEM region/grain diameter min=0.08", "--set",
      "DEM region/grain diameter max=0.12", "--set", "Continuum/outer radius=10", "--set",
      "Output/interval=0", "--set", "Output/checkpoint interval=0", "--set",
      "Coupling/equilibrium ratio=1e-12", "--set", "Coupling/step limit=2000", "--set",
      "Problem/output directory=" + dir,
      // a small region for speed, and an equilibrium ratio no phase reaches
      // within its step limit: a status to accept; the 1 m region of the
      // slit granite also has a damage-zone crack at its coupling band
      // (region_too_small), accepted too
      "--accept", "not_equilibrated,region_too_small"};
  std::vector<char *> argv;
  for (auto &a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0)
    {
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(fd, 1);
      dup2(fd, 2);
      execv(argv[0], argv.data());
      _exit(127);
    }
  bool started = false;
  for (int k = 0; k < 3000 && !started; ++k)
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      started = read(log).find("building the DEM region") != std::string::npos;
    }
  REQUIRE(started);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  const std::string text = read(log);
  INFO(text);
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 130);
  CHECK_THAT(read(dir + "/manifest.json"),
             Catch::Contains("\"status\": \"interrupted\""));

  // The hint: every --set, quoted for the shell, then --restart.
  const std::string marker = "continue with: ";
  const auto        at     = text.find(marker);
  REQUIRE(at != std::string::npos);
  const std::string hint =
      text.substr(at + marker.size(), text.find('\n', at) - at - marker.size());
  INFO("hint: " << hint);
  CHECK_THAT(hint, Catch::StartsWith("demfem tunnel " + prm));
  for (std::size_t k = 3; k < args.size(); k += 2) // quoted when it has blanks
    CHECK_THAT(hint, Catch::Contains(args[k] + " '" + args[k + 1] + "'") ||
                         Catch::Contains(args[k] + " " + args[k + 1] + " "));
  CHECK_THAT(hint, Catch::EndsWith("--restart " + dir + "/checkpoint.h5"));

  // A fresh run into the used directory is refused, naming --overwrite.
  {
    std::string again;
    for (std::size_t k = 0; k < args.size(); ++k)
      again += (k < 2 ? args[k] : "'" + args[k] + "'") + " ";
    const Run r = shell(again, log);
    INFO(r.text);
    CHECK(r.code == 1);
    CHECK_THAT(r.text, Catch::Contains("--overwrite"));
    CHECK(fs::exists(dir + "/checkpoint.h5"));
  }

  // The hint, run into another directory: complete files there.
  const std::string exe_hint = std::string(DEMFEM_EXE) + hint.substr(6);
  {
    const Run r =
        shell(exe_hint + " --set 'Problem/output directory=" + moved + "'", log);
    INFO(r.text);
    REQUIRE(r.code == 0);
    const std::string history = read(moved + "/history.csv");
    CHECK_THAT(history, Catch::StartsWith("step,time,phase,"));
    CHECK(std::count(history.begin(), history.end(), '\n') > 5);
    CHECK(fs::exists(moved + "/summary.json"));
    // The status the run reached, accepted by the --accept of the hint.
    CHECK_THAT(read(moved + "/manifest.json"),
               Catch::Contains("\"status\": \"not_equilibrated\"") &&
                   Catch::Contains("\"exit_code\": 0"));
  }

  // A damaged checkpoint (one byte of its stored .prm text changed) is
  // refused before the model is built, naming the dataset and the file.
  {
    const std::string ck    = dir + "/checkpoint.h5";
    std::string       bytes = read(ck);
    const auto        k     = bytes.find("slaved-layer");
    REQUIRE(k != std::string::npos);
    bytes[k] = 'S';
    std::ofstream(ck, std::ios::binary | std::ios::trunc) << bytes;
    const Run r = shell(exe_hint, log);
    INFO(r.text);
    CHECK(r.code == 1);
    CHECK_THAT(r.text, Catch::Contains(ck) && Catch::Contains("Fletcher32") &&
                           Catch::Contains("/metadata/values"));
    CHECK(r.text.find("building the DEM region") == std::string::npos);
  }
  fs::remove_all(tmp);
  fs::remove(log);
}
