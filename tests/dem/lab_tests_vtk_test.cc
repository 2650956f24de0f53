// VTK writers (dem/io/vtk_output.h): files re-read with VTK's own XML reader;
// arrays present with one tuple per point/cell, finite values, connectivity
// in range (no VTK reader checks it, docs/architecture.md, "VTK files"), and the .pvd paths relative.
#include "dem/laws/linear_law.h"
#include "dem/engine/model.h"
#include "dem/io/vtk_output.h"

#include <catch2/catch.hpp>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace demfem::dem;
namespace fs = std::filesystem;

namespace
{
  vtkSmartPointer<vtkPolyData> read(const std::string &path)
  {
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName(path.c_str());
    r->Update();
    vtkSmartPointer<vtkPolyData> d = r->GetOutput();
    return d;
  }

  void check_array(vtkFieldData *fd, const char *name, vtkIdType n, int components)
  {
    INFO("array " << name);
    vtkDataArray *a = fd->GetArray(name);
    REQUIRE(a != nullptr);
    CHECK(a->GetNumberOfTuples() == n);
    CHECK(a->GetNumberOfComponents() == components);
    for (vtkIdType i = 0; i < n; ++i)
      for (int c = 0; c < components; ++c)
        REQUIRE(std::isfinite(a->GetComponent(i, c)));
  }

  void check_connectivity(vtkPolyData *d, vtkCellArray *cells, vtkIdType n_cells,
                          int npts)
  {
    REQUIRE(cells->GetNumberOfCells() == n_cells);
    vtkNew<vtkIdList> ids;
    cells->InitTraversal();
    while (cells->GetNextCell(ids))
      {
        REQUIRE(ids->GetNumberOfIds() == npts);
        for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
          {
            REQUIRE(ids->GetId(k) >= 0);
            REQUIRE(ids->GetId(k) < d->GetNumberOfPoints());
          }
      }
  }

  template <int dim>
  void vtk_round_trip()
  {
    Model<dim> m;
    // A row of touching grains with a prescribed velocity on the last one.
    for (int i = 0; i < 5; ++i)
      {
        Vec<dim> x = Vec<dim>::Zero();
        x[0]       = 1.9 * i;
        m.particles.add(x, 1.0, 2650, i % 2);
      }
    typename LinearLaw<dim>::Params lp;
    lp.kn = 1e6, lp.ks = 1e6;
    m.set_default_law(m.template add_law<LinearLaw<dim>>(lp), -1);
    m.particles.v[4][0]   = 0.1;
    m.particles.fixity[4] = fix_all;
    m.cycle(10);
    const vtkIdType nc = static_cast<vtkIdType>(m.n_contacts());
    REQUIRE(nc == 4); // overlapping neighbours only (gap 0.2 - 0.1*... skin)

    CrackRecord<dim> c;
    c.position       = Vec<dim>::Constant(0.5);
    c.normal         = Vec<dim>::Zero();
    c.normal[0]      = 1;
    c.size           = 0.8;
    c.gap            = 1e-4;
    c.mode           = 1;
    c.step           = 7;
    m.cracks         = {c, c};
    m.cracks[1].mode = 0;

    const fs::path dir =
        fs::temp_directory_path() / ("demfem_vtk_test_" + std::to_string(dim));
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    const std::string fp = (dir / "sub" / "particles_0.vtp").string();
    const std::string fc = (dir / "sub" / "contacts_0.vtp").string();
    const std::string fk = (dir / "sub" / "cracks_0.vtp").string();
    vtkout::write_particles(fp, m);
    vtkout::write_contacts(fc, m);
    vtkout::write_cracks(fk, m.cracks, 12);
    vtkout::Collection pvd((dir / "particles.pvd").string());
    pvd.add(0.1 + 1e-12, fp);

    auto p = read(fp);
    REQUIRE(p->GetNumberOfPoints() == 5);
    for (const char *a : {"radius", "group", "id", "fixity"})
      check_array(p->GetPointData(), a, 5, 1);
    for (const char *a : {"velocity", "displacement", "angular_velocity"})
      check_array(p->GetPointData(), a, 5, 3);
    CHECK(p->GetPointData()->GetArray("velocity")->GetComponent(4, 0) == Approx(0.1));
    CHECK(p->GetPointData()->GetArray("group")->GetComponent(3, 0) == 1);
    check_connectivity(p, p->GetVerts(), 5, 1);

    auto q = read(fc);
    check_connectivity(q, q->GetLines(), nc, 2);
    for (const char *a : {"group", "wall", "active", "bonded", "normal_force", "gap"})
      check_array(q->GetCellData(), a, nc, 1);
    check_array(q->GetCellData(), "force", nc, 3);

    auto k = read(fk);
    if (dim == 2)
      check_connectivity(k, k->GetLines(), 2, 2);
    else
      check_connectivity(k, k->GetPolys(), 2, 12);
    for (const char *a : {"mode", "size", "gap", "step"})
      check_array(k->GetCellData(), a, 2, 1);
    CHECK(k->GetCellData()->GetArray("mode")->GetComponent(0, 0) == 1);
    // The crack's extent equals its size (segment length / disk diameter).
    double b[6];
    k->GetBounds(b);
    CHECK(b[3] - b[2] == Approx(0.8).epsilon(1e-12));

    // .pvd: relative path and time with 17 significant digits.
    std::ifstream     f(dir / "particles.pvd");
    std::stringstream s;
    s << f.rdbuf();
    CHECK(s.str().find("file=\"sub/particles_0.vtp\"") != std::string::npos);
    const auto at = s.str().find("timestep=\"");
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(s.str().substr(at + 10)) == 0.1 + 1e-12); // round-trips exactly
    // No temporary files left behind.
    for (const auto &e : fs::directory_iterator(dir / "sub"))
      CHECK(e.path().extension() != ".tmp");
    fs::remove_all(dir);
  }
} // namespace

TEST_CASE("VTK particles/contacts/cracks re-read by vtkXMLPolyDataReader",
          "[labtests][vtk]")
{
  SECTION("2D") { vtk_round_trip<2>(); }
  SECTION("3D") { vtk_round_trip<3>(); }
}
