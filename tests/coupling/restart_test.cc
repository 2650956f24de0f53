// Checkpoint / restart of the coupled tunnel run (docs/architecture.md,
// "Checkpoints and restart"): a run stopped at a step boundary and continued
// from its checkpoint gives the same results, bit for bit, as the uninterrupted
// run (the checkpoint holds the complete DEM, continuum and workflow state); a
// checkpoint written with other parameters is refused, naming it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "coupling/tunnel_run.h"
#include "helpers.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

using namespace demfem;

namespace
{
  // Small, weak specimen (cracks form during the excavation), two
  // excavation stages so that the stop falls inside the excavation. Constants
  // of apps/examples/tunnel_2d.prm (region matched to the continuum), weaker
  // bonds so that grains crack at 30/60 MPa.
  coupling::TunnelParams small(const std::string &dir)
  {
    coupling::TunnelParams p;
    p.output_directory        = dir;
    p.tunnel_radius           = 0.4;
    p.region.radius           = 1.0;
    p.region.d_lo             = 0.08;
    p.region.d_hi             = 0.12;
    p.region.emod             = 20e9;
    p.region.lnm_emod         = 20e9;
    p.region.fj_ten           = 4e6;
    p.region.fj_coh           = 20e6;
    p.continuum.young_modulus = 16.3e9;
    p.continuum.poisson_ratio = 0.11;
    p.continuum.outer_radius  = 10;
    p.stages                  = 2;
    p.phase_step_limit        = 1000;
    p.vtk_interval            = 0;
    p.write_vtk               = false;
    p.history_interval        = 50;
    p.checkpoint_interval     = 250;
    p.prm_text                = "set radius = 0.4\nset output directory = " + dir + "\n";
    return p;
  }

  std::string read(const std::string &f)
  {
    std::ifstream     in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
} // namespace

TEST_CASE("tunnel restart: stopped and continued run equals the uninterrupted one",
          "[coupling][restart]")
{
  test::ensure_mpi_coupling();
  // Both coupling variants and the three schemes (their coupling states
  // differ).
  const std::string variant =
      GENERATE(as<std::string>{}, "slaved-layer", "wall-facets",
               "slaved-layer/quasi-static", "slaved-layer/condensed");
  INFO("Coupling/variant = " << variant);
  const auto        slash = variant.find('/');
  const std::string scheme =
      slash != std::string::npos ? variant.substr(slash + 1) : std::string("explicit");
  const std::string name  = variant.substr(0, variant.find('/'));
  auto              small = [&](const std::string &dir) {
    auto p             = ::small(dir);
    p.coupling.variant = name;
    p.coupling.scheme  = scheme;
    if (scheme == "quasi-static")
      {
        p.coupling.subcycles  = 200;
        p.coupling.relaxation = 0.5;
      }
    p.prm_text += "set variant = " + variant + "\n";
    return p;
  };
  const auto        tmp = std::filesystem::temp_directory_path();
  const std::string da  = tmp / ("demfem_restart_a_" + name + "_" + scheme),
                    db  = tmp / ("demfem_restart_b_" + name + "_" + scheme);
  std::filesystem::remove_all(da);
  std::filesystem::remove_all(db);
  std::ostringstream log;

  const auto ra = coupling::run_tunnel(small(da), log);
  INFO(ra.diagnosis);
  REQUIRE_FALSE(ra.diverged);
  REQUIRE_FALSE(ra.interrupted);

  // The phases: in-situ, with the in-situ servo (slaved layer, explicit or
  // condensed; coupling/in_situ_servo.h) its corrections "in-situ servo k"
  // and "in-situ release", then in-situ cracking, two stages, equilibrium.
  const bool servoed = name == "slaved-layer" && scheme != "quasi-static";
  const auto first   = [&](const std::string &prefix) {
    for (std::size_t k = 0; k < ra.phases.size(); ++k)
      if (ra.phases[k].name.rfind(prefix, 0) == 0)
        return k;
    FAIL("no phase '" << prefix << "'");
    return ra.phases.size();
  };
  REQUIRE(ra.phases.size() >= 5);
  CHECK(ra.phases.size() - first("in-situ cracking") == 4);
  const bool released =
      std::any_of(ra.phases.begin(), ra.phases.end(),
                  [](const auto &ph) { return ph.name == "in-situ release"; });
  CHECK(released == servoed);
  // Stopped halfway through a phase (their steps are the coupled steps),
  // continued from the checkpoint: the same run bit for bit. The first
  // excavation stage, and with the servo its first correction (the
  // servo's state, its ramp and the held continuum go through the
  // checkpoint).
  std::vector<std::size_t> stops = {first("excavation 1/")};
  if (servoed)
    stops.push_back(first("in-situ servo 1"));
  for (const std::size_t stop : stops)
    {
      INFO("stopped in phase '" << ra.phases[stop].name << "'");
      REQUIRE(ra.phases[stop].steps >= 2);
      std::filesystem::remove_all(db);
      auto pb         = small(db);
      pb.stop_at_step = ra.phases[stop].steps / 2;
      for (std::size_t k = 0; k < stop; ++k)
        pb.stop_at_step += ra.phases[k].steps;
      const auto rb = coupling::run_tunnel(pb, log);
      REQUIRE(rb.interrupted);
      REQUIRE(std::filesystem::exists(db + "/checkpoint.h5"));

      auto pc         = small(db);
      pc.restart_file = db + "/checkpoint.h5";
      const auto rc   = coupling::run_tunnel(pc, log);
      REQUIRE_FALSE(rc.interrupted);
      REQUIRE_FALSE(rc.diverged);

      CHECK(rc.steps == ra.steps);
      CHECK(rc.cracks_total == ra.cracks_total);
      CHECK(rc.cracks_tensile == ra.cracks_tensile);
      CHECK(rc.n_particles == ra.n_particles);
      CHECK(rc.n_contacts == ra.n_contacts);
      // Bit for bit: every number of the state is restored exactly.
      CHECK(rc.wall_convergence_mean == ra.wall_convergence_mean);
      CHECK(rc.damage_zone_depth == ra.damage_zone_depth);
      CHECK(rc.interface_force_imbalance_max == ra.interface_force_imbalance_max);
      CHECK(rc.region_stress_before == ra.region_stress_before);
      CHECK(rc.servo.errors == ra.servo.errors);
      CHECK(rc.servo.interface_strain == ra.servo.interface_strain);
      REQUIRE(rc.positions.size() == ra.positions.size());
      std::size_t differ = 0;
      for (std::size_t i = 0; i < ra.positions.size(); ++i)
        differ += !(rc.positions[i] == ra.positions[i]);
      CHECK(differ == 0);
      // history.csv was truncated to the checkpoint and continued: identical.
      CHECK(read(db + "/history.csv") == read(da + "/history.csv"));
      // The outcome checks of the restarted run see the phases of the
      // uninterrupted one, bit for bit (phase records go through the
      // checkpoint).
      CHECK(rc.status == ra.status);
      const auto sa = nlohmann::json::parse(read(da + "/summary.json"));
      const auto sb = nlohmann::json::parse(read(db + "/summary.json"));
      CHECK(sb["status"] == sa["status"]);
      CHECK(sb["problems"] == sa["problems"]);
      CHECK(sb["phases"] == sa["phases"]);
      CHECK(sb["in_situ_servo"] == sa["in_situ_servo"]);
      CHECK(sb["cracks_by_type"]["flat_joint"] == ra.cracks_total);
    }
  INFO("cracks " << ra.cracks_total << ", convergence " << ra.wall_convergence_mean);
  CHECK(ra.cracks_total > 0); // the test exercises crack records too
  // Damage-zone cracks near the coupling boundary flag the region as too
  // small, in the result, the summary and the log.
  const auto sa = nlohmann::json::parse(read(da + "/summary.json"));
  CHECK(sa["region_too_small"] == ra.region_too_small);
  // The in-situ ramp lasts its physical duration, Coupling/ramp crossing
  // times (default 4) x the region's 2 R / sqrt(E* / rho): its steps at
  // this dt are the fewest reaching it, and the in-situ phase holds them.
  const auto  &ramp     = sa["in_situ_ramp"];
  const double duration = ramp["duration_s"].get<double>();
  const double dt       = sa["timestep_s"].get<double>();
  const auto   n_ramp   = ramp["steps"].get<std::int64_t>();
  CHECK(ramp["crossing_time_s"].get<double>() ==
        Approx(2 * 1.0 / std::sqrt(20e9 / 2650)).epsilon(1e-12));
  CHECK(duration == Approx(4 * ramp["crossing_time_s"].get<double>()).epsilon(1e-14));
  CHECK(double(n_ramp) * dt >= duration * (1 - 1e-12));
  CHECK(double(n_ramp - 1) * dt < duration);
  CHECK(ra.phases[0].steps >= n_ramp);
  CHECK(ra.region_too_small == (ra.zone_cracks_near_interface > 0));
  CHECK(ra.zone_cracks_near_interface <= ra.cracks_near_interface);
  CHECK((log.str().find("DEM region is too small") != std::string::npos) ==
        ra.region_too_small);
  // Every crack of the flat-jointed region is a flat-joint crack, counted by
  // type in summary.json; the restarted run's crack records keep their type.
  CHECK(sa["cracks_by_type"] == nlohmann::json{{"contact_bond", 0},
                                               {"parallel_bond", 0},
                                               {"flat_joint", ra.cracks_total},
                                               {"smooth_joint", 0}});
  // summary.json reports the real coupling.
  CHECK(sa["variant"] == name);
  CHECK(sa["scheme"] == scheme);
}
TEST_CASE("tunnel restart: a checkpoint of other parameters is refused",
          "[coupling][restart]")
{
  test::ensure_mpi_coupling();
  const std::string d = std::filesystem::temp_directory_path() / "demfem_restart_c";
  std::filesystem::remove_all(d);
  std::ostringstream log;
  auto               p = small(d);
  p.stop_at_step       = 10;
  REQUIRE(coupling::run_tunnel(p, log).interrupted);

  auto q         = small(d);
  q.restart_file = d + "/checkpoint.h5";
  q.prm_text     = "set radius = 0.5\nset output directory = " + d + "\n";
  try
    {
      coupling::run_tunnel(q, log);
      FAIL("a checkpoint of other parameters was accepted");
    }
  catch (const dem::InputError &e)
    {
      const std::string m = e.what();
      CHECK(m.find(q.restart_file) != std::string::npos);
      CHECK(m.find("different parameters") != std::string::npos);
      CHECK(m.find("set radius = 0.5") != std::string::npos);
    }
}

TEST_CASE("tunnel restart: SIGINT writes a checkpoint and exits cleanly",
          "[coupling][restart][app]")
{
  const std::string dir = std::filesystem::temp_directory_path() / "demfem_restart_sig";
  const std::string log = dir + ".log";
  std::filesystem::remove_all(dir);
  std::filesystem::remove(log);
  const std::string prm = std::string(DEMFEM_SOURCE_DIR) + "/apps/examples/tunnel_2d.prm";
  std::vector<std::string> args = {
      DEMFEM_EXE, "tunnel", prm, "--set", "DEM region/radius=1.0", "--set",
      "Tunnel/radius=0.4", "--set", "DEM region/grain diameter=0.1", "--set",
      "DEM region/grain diameter min=0.08", "--set", "DEM region/grain diameter max=0.12",
      "--set", "Continuum/outer radius=10", "--set", "Output/interval=0", "--set",
      "Output/checkpoint interval=0", "--set", "Problem/output directory=" + dir,
      // a region this small for speed: its
      // damage zone may reach the boundary
      "--accept", "region_too_small"};
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
  // The handler is installed before the model is built: wait for the
  // build message, then interrupt during the coupled run (~1.5 s long).
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
  CHECK(WEXITSTATUS(status) == 130);
  CHECK(text.find("checkpoint written to") != std::string::npos);
  CHECK(std::filesystem::exists(dir + "/checkpoint.h5"));
  CHECK_FALSE(std::filesystem::exists(dir + "/checkpoint.h5.tmp"));
  CHECK_FALSE(std::filesystem::exists(dir + "/summary.json")); // stopped, not done

  // ... and the run continues from it to the end.
  std::string cmd;
  for (std::size_t k = 0; k < args.size(); ++k)
    cmd += (k < 2 ? args[k] : "\"" + args[k] + "\"") + " ";
  cmd += "--restart " + dir + "/checkpoint.h5 > " + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  INFO(read(log));
  CHECK((WIFEXITED(rc) && WEXITSTATUS(rc) == 0));
  CHECK(std::filesystem::exists(dir + "/summary.json"));
}
