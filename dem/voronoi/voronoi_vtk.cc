// VTK XML output of rigid and flexible Voronoi grains (dem/voronoi/voronoi_vtk.h).
#include "dem/voronoi/voronoi_vtk.h"

#include "dem/io/vtk_polydata.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace demfem::dem::voronoi
{
  using vtkout::double_array;
  using vtkout::int_array;
  using vtkout::write_polydata;

  namespace
  {
    GrainKinematics kinematics(const RigidVoronoiModel &m)
    {
      return GrainKinematics{m.x.data(),  m.y.data(),  m.radius.data(),
                             m.vx.data(), m.vy.data(), m.omega.data()};
    }
  } // namespace

  void voronoi_grain_stress(const Tessellation &tess, const RigidVoronoiModel &m,
                            std::vector<double> &sxx, std::vector<double> &syy,
                            std::vector<double> &sxy)
  {
    const int n = m.n_grains();
    sxx.assign(n, 0.0);
    syy.assign(n, 0.0);
    sxy.assign(n, 0.0);
    // Sum of r (x) f over the forces f acting on the grain at arms r from
    // its disk centre (symmetric part), then over the cell volume.
    auto add = [&](int g, double rx, double ry, double fx, double fy) {
      sxx[g] += rx * fx;
      syy[g] += ry * fy;
      sxy[g] += 0.5 * (rx * fy + ry * fx);
    };
    const auto &c = m.contacts;
    const auto  g = kinematics(m);
    for (int k = 0; k < c.n_contacts(); ++k)
      {
        double xr, yr, nx, ny;
        c.reference_frame(k, g, xr, yr, nx, ny);
        const double tx = -ny, ty = nx;
        const int    a = c.grain_a[k], b = c.grain_b[k];
        for (int p = c.point_offset[k]; p < c.point_offset[k + 1]; ++p)
          {
            const double px = xr + c.s[p] * tx, py = yr + c.s[p] * ty;
            const double fx = -c.fn[p] * nx + c.fs[p] * tx,
                         fy = -c.fn[p] * ny + c.fs[p] * ty;
            add(b, px - m.x[b], py - m.y[b], fx, fy);
            add(a, px - m.x[a], py - m.y[a], -fx, -fy);
          }
      }
    for (int k = 0; k < static_cast<int>(m.platens.size()); ++k)
      {
        const auto &pl = m.platens[k];
        if (!pl.active)
          continue;
        const double tx = -pl.ny, ty = pl.nx;
        for (int i = pl.point_begin; i < pl.point_end; ++i)
          {
            double rx, ry;
            m.platen_point_arm(k, i, rx, ry);
            const double fx = -m.pp_fn[i] * pl.nx + m.pp_fs[i] * tx;
            const double fy = -m.pp_fn[i] * pl.ny + m.pp_fs[i] * ty;
            add(m.pp_grain[i], rx, ry, -fx, -fy); // the grain gets the opposite
          }
      }
    for (const auto &e : m.boundary_edges)
      if (m.pressure_on(e.side) != 0)
        {
          double Fx, Fy, rx, ry;
          m.pressure_force(e, Fx, Fy, rx, ry);
          add(e.grain, rx, ry, Fx, Fy);
        }
    const double t = m.contacts.thickness();
    for (int i = 0; i < n; ++i)
      {
        const double V = tess.area[i] * t;
        if (V > 0)
          {
            sxx[i] /= V;
            syy[i] /= V;
            sxy[i] /= V;
          }
      }
  }

  void write_voronoi_cells_vtk(const std::string &path, const Tessellation &tess,
                               const RigidVoronoiModel &m)
  {
    if (tess.n_cells() != m.n_grains())
      throw std::invalid_argument(
          "write_voronoi_cells_vtk: tessellation and model differ");
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble(); // micrometre displacements on metre coordinates
    vtkNew<vtkCellArray> polys;
    std::vector<int>     cells;
    for (int c = 0; c < tess.n_cells(); ++c)
      {
        if (m.held[c])
          continue;
        const double cs = std::cos(m.theta[c]), sn = std::sin(m.theta[c]);
        polys->InsertNextCell(tess.end(c) - tess.begin(c));
        for (int e = tess.begin(c); e < tess.end(c); ++e)
          {
            // The install vertex, turned and moved with its grain.
            const double rx = tess.vertex_x[e] - m.x0[c], ry = tess.vertex_y[e] - m.y0[c];
            polys->InsertCellPoint(pts->InsertNextPoint(m.x[c] + cs * rx - sn * ry,
                                                        m.y[c] + sn * rx + cs * ry, 0.0));
          }
        cells.push_back(c);
      }
    const vtkIdType n     = static_cast<vtkIdType>(cells.size());
    auto            id    = int_array("grain", n);
    auto            disp  = double_array("displacement", 3, n);
    auto            rot   = double_array("rotation", 1, n);
    auto            sigma = double_array("stress", 3, n); // xx, yy, xy (tension positive)
    std::vector<double> sxx, syy, sxy;
    voronoi_grain_stress(tess, m, sxx, syy, sxy);
    for (vtkIdType k = 0; k < n; ++k)
      {
        const int c = cells[k];
        id->SetValue(k, c);
        disp->SetTuple3(k, m.x[c] - m.x0[c], m.y[c] - m.y0[c], 0.0);
        rot->SetValue(k, m.theta[c]);
        sigma->SetTuple3(k, sxx[c], syy[c], sxy[c]);
      }
    vtkNew<vtkPolyData> data;
    data->SetPoints(pts);
    data->SetPolys(polys);
    for (vtkDataArray *a :
         {static_cast<vtkDataArray *>(id), static_cast<vtkDataArray *>(disp),
          static_cast<vtkDataArray *>(rot), static_cast<vtkDataArray *>(sigma)})
      data->GetCellData()->AddArray(a);
    write_polydata(path, data);
  }

  namespace
  {
    /// The local contact points of `c` at the grains' current disks `g`
    /// (the model's points and cracks files, rigid or flexible grains).
    void write_contact_points(const std::string &path, const RigidVoronoiContacts &c,
                              const GrainKinematics &g)
    {
      const vtkIdType   n = c.n_points();
      vtkNew<vtkPoints> pts;
      pts->SetDataTypeToDouble(); // micrometre displacements on metre coordinates
      vtkNew<vtkCellArray> verts;
      auto dt = double_array("damage_t", 1, n), ds = double_array("damage_s", 1, n);
      auto fn    = double_array("normal_force", 1, n),
           fs    = double_array("shear_force", 1, n);
      auto crack = int_array("crack", n), ga = int_array("grain_a", n),
           gb = int_array("grain_b", n);
      for (int k = 0; k < c.n_contacts(); ++k)
        {
          double xr, yr, nx, ny;
          c.reference_frame(k, g, xr, yr, nx, ny);
          for (int p = c.point_offset[k]; p < c.point_offset[k + 1]; ++p)
            {
              const vtkIdType v =
                  pts->InsertNextPoint(xr - c.s[p] * ny, yr + c.s[p] * nx, 0.0);
              verts->InsertNextCell(1, &v);
              dt->SetValue(p, c.damage_t[p]);
              ds->SetValue(p, c.damage_s[p]);
              fn->SetValue(p, c.fn[p]);
              fs->SetValue(p, c.fs[p]);
              crack->SetValue(p, static_cast<int>(c.crack[p]));
              ga->SetValue(p, c.grain_a[k]);
              gb->SetValue(p, c.grain_b[k]);
            }
        }
      vtkNew<vtkPolyData> data;
      data->SetPoints(pts);
      data->SetVerts(verts);
      for (vtkDataArray *a :
           {static_cast<vtkDataArray *>(dt), static_cast<vtkDataArray *>(ds),
            static_cast<vtkDataArray *>(fn), static_cast<vtkDataArray *>(fs),
            static_cast<vtkDataArray *>(crack), static_cast<vtkDataArray *>(ga),
            static_cast<vtkDataArray *>(gb)})
        data->GetPointData()->AddArray(a);
      write_polydata(path, data);
    }

    /// The cracked local points of `c` as pieces of their cell edges.
    int write_contact_cracks(const std::string &path, const RigidVoronoiContacts &c,
                             const GrainKinematics &g)
    {
      vtkNew<vtkPoints> pts;
      pts->SetDataTypeToDouble(); // micrometre displacements on metre coordinates
      vtkNew<vtkCellArray> lines;
      std::vector<int>     mode, ga, gb;
      for (int k = 0; k < c.n_contacts(); ++k)
        {
          const int p0 = c.point_offset[k], np = c.point_offset[k + 1] - p0;
          double    xr, yr, nx, ny;
          c.reference_frame(k, g, xr, yr, nx, ny);
          // Edge ends along the tangent: the outer points (Lobatto) or the
          // middle -+ L/2 (one point).
          const double L  = c.edge_length[k];
          const double s0 = np == 3 ? c.s[p0] : c.s[p0] - L / 2;
          const double s1 = np == 3 ? c.s[p0 + 2] : c.s[p0] + L / 2;
          const double d  = (s1 - s0) / 6; // a sixth of the edge (Lobatto weights)
          for (int i = 0; i < np; ++i)
            {
              const int p = p0 + i;
              if (c.crack[p] != PointCrack::tensile && c.crack[p] != PointCrack::shear)
                continue;
              double a = s0, b = s1;
              if (np == 3)
                {
                  a = i == 0 ? s0 : i == 1 ? s0 + d : s1 - d;
                  b = i == 0 ? s0 + d : i == 1 ? s1 - d : s1;
                }
              const vtkIdType ends[2] = {
                  pts->InsertNextPoint(xr - a * ny, yr + a * nx, 0.0),
                  pts->InsertNextPoint(xr - b * ny, yr + b * nx, 0.0)};
              lines->InsertNextCell(2, ends);
              mode.push_back(static_cast<int>(c.crack[p]));
              ga.push_back(c.grain_a[k]);
              gb.push_back(c.grain_b[k]);
            }
        }
      const vtkIdType n  = static_cast<vtkIdType>(mode.size());
      auto            md = int_array("mode", n), a = int_array("grain_a", n),
           b = int_array("grain_b", n);
      for (vtkIdType k = 0; k < n; ++k)
        {
          md->SetValue(k, mode[k]);
          a->SetValue(k, ga[k]);
          b->SetValue(k, gb[k]);
        }
      vtkNew<vtkPolyData> data;
      data->SetPoints(pts);
      data->SetLines(lines);
      for (vtkDataArray *x :
           {static_cast<vtkDataArray *>(md), static_cast<vtkDataArray *>(a),
            static_cast<vtkDataArray *>(b)})
        data->GetCellData()->AddArray(x);
      write_polydata(path, data);
      return static_cast<int>(n);
    }
  } // namespace

  void write_voronoi_points_vtk(const std::string &path, const RigidVoronoiModel &m)
  {
    write_contact_points(path, m.contacts, kinematics(m));
  }

  int write_voronoi_cracks_vtk(const std::string &path, const RigidVoronoiModel &m)
  {
    return write_contact_cracks(path, m.contacts, kinematics(m));
  }

  namespace
  {
    /// Current disks of flexible grains (centroid node + install offset).
    struct FlexibleDisks
    {
      std::vector<double> x, y;
      GrainKinematics     kinematics;
      explicit FlexibleDisks(const FlexibleVoronoiModel &m)
      {
        for (int c = 0; c < m.n_grains(); ++c)
          {
            x.push_back(m.disk_x(c));
            y.push_back(m.disk_y(c));
          }
        kinematics = GrainKinematics{x.data(), y.data(), m.disk_radius.data()};
      }
    };
  } // namespace

  void write_voronoi_cells_vtk(const std::string &path, const FlexibleVoronoiModel &m)
  {
    const auto       &mesh = m.mesh;
    const vtkIdType   nn   = mesh.n_nodes();
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble(); // micrometre displacements on metre coordinates
    auto disp = double_array("displacement", 3, nn);
    for (vtkIdType a = 0; a < nn; ++a)
      {
        pts->InsertNextPoint(m.x[a], m.y[a], 0.0);
        disp->SetTuple3(a, m.x[a] - mesh.x0[a], m.y[a] - mesh.y0[a], 0.0);
      }
    vtkNew<vtkCellArray> polys;
    const vtkIdType      ne    = mesh.n_triangles();
    auto                 grain = int_array("grain", ne);
    auto sigma = double_array("stress", 3, ne); // Cauchy xx, yy, xy (tension positive)
    auto mean  = double_array("mean_stress", 1, ne);
    for (vtkIdType e = 0; e < ne; ++e)
      {
        const vtkIdType v[3] = {mesh.triangle_nodes[3 * e],
                                mesh.triangle_nodes[3 * e + 1],
                                mesh.triangle_nodes[3 * e + 2]};
        polys->InsertNextCell(3, v);
        double s[4];
        mesh.cauchy_stress(static_cast<int>(e), m.x.data(), m.y.data(), s);
        grain->SetValue(e, mesh.node_grain[v[0]]);
        sigma->SetTuple3(e, s[0], s[1], s[2]);
        mean->SetValue(e, (s[0] + s[1] + s[3]) / 3); // with the plane-strain s_zz
      }
    vtkNew<vtkPolyData> data;
    data->SetPoints(pts);
    data->SetPolys(polys);
    data->GetPointData()->AddArray(disp);
    for (vtkDataArray *a :
         {static_cast<vtkDataArray *>(grain), static_cast<vtkDataArray *>(sigma),
          static_cast<vtkDataArray *>(mean)})
      data->GetCellData()->AddArray(a);
    write_polydata(path, data);
  }

  void write_voronoi_points_vtk(const std::string &path, const FlexibleVoronoiModel &m)
  {
    const FlexibleDisks d(m);
    write_contact_points(path, m.contacts, d.kinematics);
  }

  int write_voronoi_cracks_vtk(const std::string &path, const FlexibleVoronoiModel &m)
  {
    const FlexibleDisks d(m);
    return write_contact_cracks(path, m.contacts, d.kinematics);
  }
} // namespace demfem::dem::voronoi
