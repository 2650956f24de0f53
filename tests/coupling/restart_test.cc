// Checkpoint / restart of the coupled tunnel run (issue 5, DESIGN §8): a run
// stopped at a step boundary and continued from its checkpoint gives the
// same results, bit for bit, as the uninterrupted run (the checkpoint holds
// the complete DEM, continuum and workflow state); a checkpoint written with
// other parameters is refused, naming it.
#include <catch2/catch.hpp>

#include "coupling/tunnel_run.h"
#include "helpers.h"

#include <filesystem>
#include <fstream>
#include <sstream>

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
    p.ramp_steps              = 2000;
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
  const auto        tmp = std::filesystem::temp_directory_path();
  const std::string da = tmp / "demfem_restart_a", db = tmp / "demfem_restart_b";
  std::filesystem::remove_all(da);
  std::filesystem::remove_all(db);
  std::ostringstream log;

  const auto ra = coupling::run_tunnel(small(da), log);
  INFO(ra.diagnosis);
  REQUIRE_FALSE(ra.diverged);
  REQUIRE_FALSE(ra.interrupted);

  // Stopped after 3300 coupled steps: inside the first excavation stage
  // (2000 ramp steps + at most 1000 in-situ equilibrium steps before it).
  auto pb         = small(db);
  pb.stop_at_step = 3300;
  const auto rb   = coupling::run_tunnel(pb, log);
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
  REQUIRE(rc.positions.size() == ra.positions.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < ra.positions.size(); ++i)
    differ += !(rc.positions[i] == ra.positions[i]);
  CHECK(differ == 0);
  // history.csv was truncated to the checkpoint and continued: identical.
  CHECK(read(db + "/history.csv") == read(da + "/history.csv"));
  INFO("cracks " << ra.cracks_total << ", convergence " << ra.wall_convergence_mean);
  CHECK(ra.cracks_total > 0); // the test exercises crack records too
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
