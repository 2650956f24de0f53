// Output files are replaced atomically (common/atomic_file.h): the new text
// or, on failure, the old file untouched, no temporary left behind and an
// error naming the file and the reason.
#include "common/atomic_file.h"
#include "common/json_number.h"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace fs = std::filesystem;

namespace
{
  std::string read(const fs::path &f)
  {
    std::ifstream     in(f, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
} // namespace

TEST_CASE("atomic file: replaces the whole file, or nothing", "[io]")
{
  const fs::path dir =
      fs::temp_directory_path() / ("demfem_atomic_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path f = dir / "summary.json";

  demfem::write_file_atomically(f.string(), "old\n");
  demfem::write_file_atomically(f.string(), std::string("new\0text\n", 9));
  CHECK(read(f) == std::string("new\0text\n", 9)); // binary-safe, whole
  CHECK_FALSE(fs::exists(dir / "summary.json.tmp"));

  // The temporary cannot be created (a directory stands in its place): the
  // old file stays as it was and the error names the file.
  fs::create_directories(dir / "summary.json.tmp");
  try
    {
      demfem::write_file_atomically(f.string(), "lost\n");
      FAIL("a failed write was not reported");
    }
  catch (const std::runtime_error &e)
    {
      CHECK_THAT(e.what(), Catch::Contains("cannot write " + f.string()));
    }
  CHECK(read(f) == std::string("new\0text\n", 9));
  fs::remove_all(dir);
}

TEST_CASE("json numbers: non-finite as null, integral as integer", "[io]")
{
  CHECK(demfem::json_number(std::numeric_limits<double>::quiet_NaN()).is_null());
  CHECK(demfem::json_number(-HUGE_VAL).is_null());
  CHECK(demfem::json_number(5e10).dump() == "50000000000");
  CHECK(demfem::json_number(0.2).dump() == "0.2");
}
