// VTK XML writers of the DEM model (see vtk_output.h).
#include "dem/io/vtk_output.h"
#include "dem/io/vtk_polydata.h"

#include "common/atomic_file.h"

#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/parallel_bond_law.h"
#include "dem/measure/particle_stress.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace demfem::dem::vtkout
{
  vtkSmartPointer<vtkDoubleArray> double_array(const char *name, int components,
                                               vtkIdType n)
  {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(n);
    return a;
  }

  vtkSmartPointer<vtkIntArray> int_array(const char *name, vtkIdType n)
  {
    auto a = vtkSmartPointer<vtkIntArray>::New();
    a->SetName(name);
    a->SetNumberOfTuples(n);
    return a;
  }

  void write_polydata(const std::string &path, vtkPolyData *data)
  {
    const std::string            tmp = path + ".tmp"; // same folder: atomic rename
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(data);
    w->SetDataModeToAppended();
    w->EncodeAppendedDataOff();
    if (w->Write() != 1)
      {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write VTK file " + path);
      }
    std::filesystem::rename(tmp, path);
  }

  namespace
  {
    namespace fs = std::filesystem;

    template <int dim>
    std::array<double, 3> p3(const Vec<dim> &x)
    {
      return {x[0], x[1], dim == 3 ? x[dim - 1] : 0.0};
    }

    /// Fraction of the interface that is bonded, by law (0 for unbonded laws).
    template <int dim>
    double bonded_fraction(const ContactGroupBase<dim> &g, std::size_t k)
    {
      if (auto fj = dynamic_cast<const ContactGroup<dim, FlatJointLaw<dim>> *>(&g))
        return double(FlatJointLaw<dim>::bonded_count(fj->params, g.state(k))) /
               FlatJointLaw<dim>::element_count(fj->params);
      if (dynamic_cast<const ContactGroup<dim, ParallelBondLaw<dim>> *>(&g))
        return ParallelBondLaw<dim>::bonded(g.state(k)) ? 1.0 : 0.0;
      if (dynamic_cast<const ContactGroup<dim, ContactBondLaw<dim>> *>(&g))
        return ContactBondLaw<dim>::bonded(g.state(k)) ? 1.0 : 0.0;
      return 0.0;
    }

    /// Where a group keeps the properties the contacts VTK shows: tensile
    /// and shear strength (cohesion) as stresses, initial microstructural
    /// type (flat joint). -1: the law has none. Contact-bond strengths are
    /// forces (Table 3 draws stresses, the rule multiplies by the cross
    /// section): shown divided by the same cross section.
    struct ShownProperties
    {
      std::string ten, shear, mtype;
      bool        force_strengths = false;
    };
    ShownProperties shown_properties(const std::vector<std::string> &names)
    {
      ShownProperties s;
      auto            has = [&](const char *n) {
        return std::find(names.begin(), names.end(), n) != names.end();
      };
      for (const char *p : {"fj", "pb", "sj"})
        if (has((std::string(p) + "_ten").c_str()))
          s.ten = std::string(p) + "_ten", s.shear = std::string(p) + "_coh";
      if (has("cb_tenf"))
        s.ten = "cb_tenf", s.shear = "cb_shearf", s.force_strengths = true;
      if (has("fj_mtype"))
        s.mtype = "fj_mtype";
      return s;
    }
  } // namespace

  void write_text_atomically(const std::string &path, const std::string &text)
  {
    write_file_atomically(path, text);
  }

  template <int dim>
  void write_particles(const std::string &path, const Model<dim> &model,
                       double solid_fraction)
  {
    const auto       &p     = model.particles;
    const auto        sigma = grain_stresses(model, solid_fraction);
    const vtkIdType   n     = static_cast<vtkIdType>(p.size());
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetNumberOfPoints(n);
    auto                 radius = double_array("radius", 1, n);
    auto                 vel    = double_array("velocity", 3, n);
    auto                 disp   = double_array("displacement", 3, n);
    auto                 omega  = double_array("angular_velocity", 3, n);
    auto                 group  = int_array("group", n);
    auto                 id     = int_array("id", n);
    auto                 fix    = int_array("fixity", n);
    auto                 stress = double_array("averaged_stress", 9, n);
    vtkNew<vtkCellArray> verts;
    for (vtkIdType i = 0; i < n; ++i)
      {
        const auto x = p3<dim>(p.x[i]);
        pts->SetPoint(i, x.data());
        radius->SetValue(i, p.radius[i]);
        vel->SetTuple(i, p3<dim>(p.v[i]).data());
        disp->SetTuple(i, p3<dim>(Vec<dim>(p.x[i] - p.x0[i])).data());
        std::array<double, 3> w{0, 0, 0};
        if constexpr (dim == 2)
          w[2] = p.w[i][0];
        else
          w = {p.w[i][0], p.w[i][1], p.w[i][2]};
        omega->SetTuple(i, w.data());
        group->SetValue(i, p.group[i]);
        id->SetValue(i, static_cast<int>(p.id[i]));
        fix->SetValue(i, p.fixity[i]);
        std::array<double, 9> t{};
        for (int a = 0; a < dim; ++a)
          for (int b = 0; b < dim; ++b)
            t[3 * a + b] = sigma[i](a, b);
        stress->SetTuple(i, t.data());
        verts->InsertNextCell(1, &i);
      }
    vtkNew<vtkPolyData> data;
    data->SetPoints(pts);
    data->SetVerts(verts);
    for (vtkDataArray *a :
         {static_cast<vtkDataArray *>(radius), static_cast<vtkDataArray *>(vel),
          static_cast<vtkDataArray *>(disp), static_cast<vtkDataArray *>(omega),
          static_cast<vtkDataArray *>(group), static_cast<vtkDataArray *>(id),
          static_cast<vtkDataArray *>(fix), static_cast<vtkDataArray *>(stress)})
      data->GetPointData()->AddArray(a);
    data->GetPointData()->SetActiveScalars("radius");
    write_polydata(path, data);
  }

  template <int dim>
  void write_contacts(const std::string &path, const Model<dim> &model)
  {
    const auto &p = model.particles;
    std::size_t n = 0;
    for (int g = 0; g < model.n_groups(); ++g)
      n += model.group(g).size();
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    vtkNew<vtkCellArray> lines;
    const vtkIdType      nc     = static_cast<vtkIdType>(n);
    auto                 group  = int_array("group", nc);
    auto                 wall   = int_array("wall", nc);
    auto                 active = int_array("active", nc);
    auto                 bonded = double_array("bonded", 1, nc);
    auto                 force  = double_array("force", 3, nc);
    auto                 fn     = double_array("normal_force", 1, nc);
    auto                 gap    = double_array("gap", 1, nc);
    // Per-contact properties (memo §1.9): the translational stiffness [N/m]
    // (memo Eq. 41, whatever the law's units), strengths, initial type.
    auto      kn    = double_array("kn", 1, nc);
    auto      ten   = double_array("tensile_strength", 1, nc);
    auto      shear = double_array("cohesion", 1, nc);
    auto      mtype = int_array("initial_type", nc);
    auto      btype = int_array("bond_type", nc);
    vtkIdType c     = 0;
    for (int g = 0; g < model.n_groups(); ++g)
      {
        const auto           &grp   = model.group(g);
        const ShownProperties shown = shown_properties(grp.property_names());
        for (std::size_t k = 0; k < grp.size(); ++k, ++c)
          {
            const Vec<dim> a = p.x[grp.end1[k]];
            const Vec<dim> b = grp.is_wall[k] ? grp.xc[k] : p.x[grp.end2[k]];
            vtkIdType      ids[2];
            ids[0] = pts->InsertNextPoint(p3<dim>(a).data());
            ids[1] = pts->InsertNextPoint(p3<dim>(b).data());
            lines->InsertNextCell(2, ids);
            group->SetValue(c, g);
            wall->SetValue(c, grp.is_wall[k] ? 1 : 0);
            active->SetValue(c, grp.active(k) ? 1 : 0);
            bonded->SetValue(c, bonded_fraction(grp, k));
            force->SetTuple(c, p3<dim>(grp.force[k]).data());
            fn->SetValue(c, grp.local_force[k].Fn);
            gap->SetValue(c, grp.gap[k]);
            kn->SetValue(c, grp.stiffness(k, p).kn);
            double area = 1;
            if (shown.force_strengths)
              {
                const double r = grp.is_wall[k] ? p.radius[grp.end1[k]]
                                                : std::min(p.radius[grp.end1[k]],
                                                           p.radius[grp.end2[k]]);
                area           = dim == 2 ? 2 * r : M_PI * r * r;
              }
            ten->SetValue(c, shown.ten.empty() ? 0.0 : grp.property(k, shown.ten) / area);
            shear->SetValue(c, shown.shear.empty() ? 0.0
                                                   : grp.property(k, shown.shear) / area);
            mtype->SetValue(c, shown.mtype.empty()
                                   ? 0
                                   : static_cast<int>(grp.property(k, shown.mtype)));
            btype->SetValue(c, static_cast<int>(grp.bond_type()));
          }
      }
    vtkNew<vtkPolyData> data;
    data->SetPoints(pts);
    data->SetLines(lines);
    for (vtkDataArray *a :
         {static_cast<vtkDataArray *>(group), static_cast<vtkDataArray *>(wall),
          static_cast<vtkDataArray *>(active), static_cast<vtkDataArray *>(bonded),
          static_cast<vtkDataArray *>(force), static_cast<vtkDataArray *>(fn),
          static_cast<vtkDataArray *>(gap), static_cast<vtkDataArray *>(kn),
          static_cast<vtkDataArray *>(ten), static_cast<vtkDataArray *>(shear),
          static_cast<vtkDataArray *>(mtype), static_cast<vtkDataArray *>(btype)})
      data->GetCellData()->AddArray(a);
    write_polydata(path, data);
  }

  template <int dim>
  void write_cracks(const std::string &path, const std::vector<CrackRecord<dim>> &cracks,
                    int disk_sides)
  {
    const vtkIdType   n = static_cast<vtkIdType>(cracks.size());
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    vtkNew<vtkCellArray> cells;
    auto                 mode   = int_array("mode", n);
    auto                 type   = int_array("type", n); // BondType
    auto                 size   = double_array("size", 1, n);
    auto                 gap    = double_array("gap", 1, n);
    auto                 step   = int_array("step", n);
    auto                 normal = double_array("normal", 3, n);
    for (vtkIdType c = 0; c < n; ++c)
      {
        const auto &r = cracks[c];
        const auto  x = p3<dim>(r.position);
        const auto  m = p3<dim>(r.normal);
        // In-plane directions of the failed interface (perpendicular to n).
        Eigen::Vector3d nn(m[0], m[1], m[2]);
        if (nn.norm() > 0)
          nn.normalize();
        else
          nn = Eigen::Vector3d::UnitX();
        const Eigen::Vector3d c0(x[0], x[1], x[2]);
        const double          half = 0.5 * r.size;
        if constexpr (dim == 2)
          {
            const Eigen::Vector3d t(-nn[1], nn[0], 0.0);
            vtkIdType             ids[2];
            const Eigen::Vector3d a = c0 - half * t, b = c0 + half * t;
            ids[0] = pts->InsertNextPoint(a.data());
            ids[1] = pts->InsertNextPoint(b.data());
            cells->InsertNextCell(2, ids);
          }
        else
          {
            const Eigen::Vector3d  helper = std::abs(nn[0]) < 0.9
                                                ? Eigen::Vector3d::UnitX()
                                                : Eigen::Vector3d::UnitY();
            const Eigen::Vector3d  s      = nn.cross(helper).normalized();
            const Eigen::Vector3d  t      = nn.cross(s);
            std::vector<vtkIdType> ids(disk_sides);
            for (int j = 0; j < disk_sides; ++j)
              {
                const double          phi = 2 * M_PI * j / disk_sides;
                const Eigen::Vector3d q =
                    c0 + half * (std::cos(phi) * s + std::sin(phi) * t);
                ids[j] = pts->InsertNextPoint(q.data());
              }
            cells->InsertNextCell(disk_sides, ids.data());
          }
        mode->SetValue(c, r.mode);
        type->SetValue(c, static_cast<int>(r.type));
        size->SetValue(c, r.size);
        gap->SetValue(c, r.gap);
        step->SetValue(c, static_cast<int>(r.step));
        normal->SetTuple(c, nn.data());
      }
    vtkNew<vtkPolyData> data;
    data->SetPoints(pts);
    if (dim == 2)
      data->SetLines(cells);
    else
      data->SetPolys(cells);
    for (vtkDataArray *a :
         {static_cast<vtkDataArray *>(mode), static_cast<vtkDataArray *>(type),
          static_cast<vtkDataArray *>(size), static_cast<vtkDataArray *>(gap),
          static_cast<vtkDataArray *>(step), static_cast<vtkDataArray *>(normal)})
      data->GetCellData()->AddArray(a);
    write_polydata(path, data);
  }

  void Collection::add(double time, const std::string &file)
  {
    const fs::path base = fs::absolute(fs::path(path_)).parent_path();
    entries_.emplace_back(time, fs::relative(fs::absolute(file), base).generic_string());
    write();
  }

  void Collection::write() const
  {
    std::ostringstream s;
    s << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" "
         "byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
    s << std::setprecision(17);
    for (const auto &[t, f] : entries_)
      s << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << f
        << "\"/>\n";
    s << "  </Collection>\n</VTKFile>\n";
    write_text_atomically(path_, s.str());
  }

  template void write_particles<2>(const std::string &, const Model<2> &, double);
  template void write_particles<3>(const std::string &, const Model<3> &, double);
  template void write_contacts<2>(const std::string &, const Model<2> &);
  template void write_contacts<3>(const std::string &, const Model<3> &);
  template void write_cracks<2>(const std::string &, const std::vector<CrackRecord<2>> &,
                                int);
  template void write_cracks<3>(const std::string &, const std::vector<CrackRecord<3>> &,
                                int);
} // namespace demfem::dem::vtkout
