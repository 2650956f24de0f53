#include "fem/mesh.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/manifold_lib.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace demfem::fem
{
  using namespace dealii;

  namespace
  {
    // Distance from the tunnel axis (the origin in 2D, the z axis in 3D).
    template <int dim>
    double axial_distance(const Point<dim> &p)
    {
      return std::hypot(p[0], p[1]);
    }
  } // namespace

  template <int dim>
  void generate_tunnel_mesh(Triangulation<dim> &tria, const GeneratedMeshSettings &s)
  {
    AssertThrow(s.radius > 0, ExcMessage("Tunnel/radius must be > 0"));
    std::ostringstream msg;
    msg << "Continuum/outer radius (" << s.outer_radius
        << ") must be larger than Tunnel/radius (" << s.radius << ")";
    AssertThrow(s.outer_radius > s.radius, ExcMessage(msg.str()));
    AssertThrow(s.cells_around >= 8, ExcMessage("need >= 8 cells around"));

    const unsigned int n_t = s.cells_around;
    // Geometric grading r_i = a (R/a)^(i/n_r): radial size ~ r ln(R/a)/n_r,
    // tangential size ~ 2 pi r/n_t; equal when n_r = n_t ln(R/a)/(2 pi).
    const unsigned int n_r = std::max<unsigned int>(
        2, static_cast<unsigned int>(std::lround(
               n_t * std::log(s.outer_radius / s.radius) / (2 * numbers::PI))));
    const unsigned int n_z = (dim == 3 ? std::max(1u, s.layers) : 0);

    const auto radius_at = [&](unsigned int i) {
      return s.radius * std::pow(s.outer_radius / s.radius, double(i) / n_r);
    };
    // Vertex numbering: (i radial, j angular, k axial).
    const auto vertex_index = [&](unsigned int i, unsigned int j, unsigned int k) {
      return (k * n_t + (j % n_t)) * (n_r + 1) + i;
    };

    std::vector<Point<dim>> vertices;
    for (unsigned int k = 0; k <= n_z; ++k)
      for (unsigned int j = 0; j < n_t; ++j)
        for (unsigned int i = 0; i <= n_r; ++i)
          {
            const double phi = 2 * numbers::PI * j / n_t;
            Point<dim>   p;
            p[0] = radius_at(i) * std::cos(phi);
            p[1] = radius_at(i) * std::sin(phi);
            if constexpr (dim == 3)
              p[2] = s.thickness * k / n_z;
            vertices.push_back(p);
          }

    // Local axes: xi radial, eta angular (counter-clockwise), zeta axial;
    // this is right-handed, so deal.II's lexicographic vertex order gives a
    // positive Jacobian.
    std::vector<CellData<dim>> cells;
    for (unsigned int k = 0; k < std::max(1u, n_z); ++k)
      for (unsigned int j = 0; j < n_t; ++j)
        for (unsigned int i = 0; i < n_r; ++i)
          {
            CellData<dim> c;
            unsigned int  v = 0;
            for (unsigned int dk = 0; dk < (dim == 3 ? 2u : 1u); ++dk)
              for (unsigned int dj = 0; dj < 2; ++dj)
                for (unsigned int di = 0; di < 2; ++di)
                  c.vertices[v++] = vertex_index(i + di, j + dj, k + dk);
            c.material_id = 0;
            cells.push_back(c);
          }
    tria.create_triangulation(vertices, cells, SubCellData());

    const double tol = 1e-8 * s.outer_radius;
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            const Point<dim> c          = face->center();
            bool             on_z_plane = false;
            if constexpr (dim == 3)
              on_z_plane = std::abs(c[2]) < tol || std::abs(c[2] - s.thickness) < tol;
            if (on_z_plane)
              face->set_boundary_id(s.plane_strain_slab ? boundary_id::roller_z
                                                        : boundary_id::far_field);
            else if (axial_distance(c) < 0.5 * (s.radius + radius_at(1)))
              face->set_boundary_id(boundary_id::tunnel_wall);
            else
              face->set_boundary_id(boundary_id::far_field);
          }

    tria.set_all_manifold_ids(0);
    if constexpr (dim == 2)
      tria.set_manifold(0, SphericalManifold<2>(Point<2>()));
    else
      tria.set_manifold(0, CylindricalManifold<3>(2));
  }

  void generate_section_mesh(Triangulation<3> &tria, const SectionMeshSettings &s)
  {
    const double a = s.tunnel_radius, r_in = s.hole_radius, t = s.section_length,
                 h = s.end_overlap, L = s.extension, R = s.outer_radius;
    AssertThrow(a > 0 && r_in > a && R > r_in && s.cells_around >= 8,
                ExcMessage("section mesh: need 0 < tunnel radius < hole radius < outer "
                           "radius and >= 8 cells around"));
    AssertThrow(h > 0 && t > 2 * h && L > 0 && s.element_size > 0,
                ExcMessage("section mesh: need 0 < end overlap < section length / 2, "
                           "extension > 0 and element size > 0"));
    const unsigned int n_t = s.cells_around;

    // Radii: uniform a .. r_in (the ring around the tunnel that the section
    // replaces), then geometric r_in .. R with cells about square (as
    // generate_tunnel_mesh).
    std::vector<double> radii;
    const unsigned int  n_a = std::max<unsigned int>(
        1, static_cast<unsigned int>(std::lround((r_in - a) / s.element_size)));
    for (unsigned int i = 0; i < n_a; ++i)
      radii.push_back(a + (r_in - a) * i / n_a);
    const unsigned int n_r =
        std::max<unsigned int>(2, static_cast<unsigned int>(std::lround(
                                      n_t * std::log(R / r_in) / (2 * numbers::PI))));
    for (unsigned int i = 0; i <= n_r; ++i)
      radii.push_back(r_in * std::pow(R / r_in, double(i) / n_r));
    const double growth = std::pow(R / r_in, 1.0 / n_r);

    // Layers: the end overlaps one layer each, the hole uniform, outwards
    // geometric with the radial growth ratio, scaled to end exactly at L.
    std::vector<double> z     = {0, h};
    const unsigned int  n_mid = std::max<unsigned int>(
        1, static_cast<unsigned int>(std::lround((t - 2 * h) / s.element_size)));
    for (unsigned int k = 1; k <= n_mid; ++k)
      z.push_back(h + (t - 2 * h) * k / n_mid);
    z.push_back(t);
    std::vector<double> steps;
    double              sum = 0;
    for (double dz = std::min(h, L) * growth; sum < L - 1e-12 * L; dz *= growth)
      {
        steps.push_back(dz);
        sum += dz;
      }
    std::vector<double> zs;
    double              acc = 0;
    for (const double dz : steps)
      {
        acc += dz * L / sum;
        zs.push_back(acc);
      }
    zs.back() = L;
    for (const double dz : zs)
      {
        z.insert(z.begin(), -dz);
        z.push_back(t + dz);
      }

    const unsigned int n_rad = radii.size(), n_z = z.size();
    const auto vertex_index = [&](unsigned int i, unsigned int j, unsigned int k) {
      return (k * n_t + (j % n_t)) * n_rad + i;
    };
    std::vector<Point<3>> vertices;
    for (unsigned int k = 0; k < n_z; ++k)
      for (unsigned int j = 0; j < n_t; ++j)
        for (unsigned int i = 0; i < n_rad; ++i)
          {
            const double phi = 2 * numbers::PI * j / n_t;
            vertices.emplace_back(radii[i] * std::cos(phi), radii[i] * std::sin(phi),
                                  z[k]);
          }
    // Right-handed local axes (radial, angular, axial) as generate_tunnel_mesh.
    std::vector<CellData<3>> cells;
    const double             tol = 1e-9 * R;
    for (unsigned int k = 0; k + 1 < n_z; ++k)
      for (unsigned int j = 0; j < n_t; ++j)
        for (unsigned int i = 0; i + 1 < n_rad; ++i)
          {
            const double zc = 0.5 * (z[k] + z[k + 1]);
            if (i < n_a && zc > h + tol && zc < t - h - tol)
              continue; // the hole: the free core of the DEM section
            CellData<3>  c;
            unsigned int v = 0;
            for (unsigned int dk = 0; dk < 2; ++dk)
              for (unsigned int dj = 0; dj < 2; ++dj)
                for (unsigned int di = 0; di < 2; ++di)
                  c.vertices[v++] = vertex_index(i + di, j + dj, k + dk);
            c.material_id = 0;
            cells.push_back(c);
          }
    SubCellData none;
    GridTools::delete_unused_vertices(vertices, cells, none);
    tria.create_triangulation(vertices, cells, none);

    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          {
            const Point<3> c = face->center();
            if (std::abs(c[2] + L) < tol || std::abs(c[2] - t - L) < tol)
              face->set_boundary_id(boundary_id::roller_z);
            else if (axial_distance(c) > 0.5 * (radii[n_rad - 2] + R))
              face->set_boundary_id(boundary_id::far_field);
            else if (axial_distance(c) < 0.5 * (a + radii[1]) && (c[2] < 0 || c[2] > t))
              face->set_boundary_id(boundary_id::tunnel_wall);
            else
              face->set_boundary_id(boundary_id::interface);
          }
    tria.set_all_manifold_ids(0);
    tria.set_manifold(0, CylindricalManifold<3>(2));
  }

  namespace
  {
    // The section headers of a Gmsh file agree with its $MeshFormat and
    // announce no more entries than the file can hold (each takes at least
    // two bytes): a body of one version under the header of another made
    // the reader allocate from whatever numbers it found, growing without
    // bound. 2.x: "$Nodes" then one count; 4.x: four numbers (blocks,
    // count, smallest tag, largest tag), as for $Elements.
    void check_gmsh_sections(const std::string &file)
    {
      std::ifstream in(file, std::ios::binary | std::ios::ate);
      const double  bytes = double(in.tellg());
      in.seekg(0);
      auto fail = [&](const std::string &what) {
        AssertThrow(false, ExcMessage("Continuum/mesh: '" + file +
                                      "' is not a consistent Gmsh mesh: " + what));
      };
      std::string line, version;
      while (std::getline(in, line))
        {
          if (line.rfind("$MeshFormat", 0) == 0)
            {
              std::getline(in, line);
              std::istringstream f(line);
              f >> version;
              if (version.empty() || (version[0] != '2' && version[0] != '4'))
                fail("$MeshFormat version '" + version + "' (allowed: 2.2, 4.1)");
            }
          else if (line.rfind("$Nodes", 0) == 0 || line.rfind("$Elements", 0) == 0)
            {
              const std::string section = line.substr(0, line.find_first_of(" \r"));
              std::getline(in, line);
              std::istringstream       h(line);
              std::vector<long double> v;
              for (long double x; h >> x;)
                v.push_back(x);
              const std::size_t expected = version[0] == '4' ? 4 : 1;
              if (version.empty() || v.size() != expected || !h.eof())
                fail("the line after " + section + " is '" + line + "'; a version " +
                     (version.empty() ? "?" : version) + " file has " +
                     std::to_string(expected) + " number(s) there");
              // The counts (4.x: blocks and entries; tags may be sparse).
              for (std::size_t k = 0; k < std::min<std::size_t>(v.size(), 2); ++k)
                if (const long double x = v[k]; !(x >= 0) || x > bytes)
                  fail(section + " announces " + std::to_string(double(x)) +
                       " entries, more than the file's " + std::to_string(bytes) +
                       " bytes can hold");
            }
        }
    }
  } // namespace

  template <int dim>
  void read_gmsh_mesh(Triangulation<dim> &tria, const std::string &file)
  {
    std::ifstream in(file);
    AssertThrow(in.good(),
                ExcMessage("Continuum/mesh: cannot open mesh file '" + file + "'"));
    check_gmsh_sections(file);
    GridIn<dim> grid_in;
    grid_in.attach_triangulation(tria);
    try
      {
        grid_in.read_msh(in);
      }
    catch (const std::exception &e)
      {
        AssertThrow(false,
                    ExcMessage("Continuum/mesh: cannot read '" + file + "' as a " +
                               std::to_string(dim) +
                               "D quadrilateral/hexahedral Gmsh mesh: " + e.what()));
      }

    // Circular boundaries (far field, interface, wall) get a manifold so
    // that refinement and MappingQ follow the circle; faces that are not on
    // one circle around the axis (e.g. the tunnel face) stay flat.
    for (const types::boundary_id id :
         {boundary_id::far_field, boundary_id::interface, boundary_id::tunnel_wall})
      {
        bool any = false;
        for (const auto &cell : tria.active_cell_iterators())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == id)
              {
                double rmin = 1e300, rmax = 0;
                for (const unsigned int v : face->vertex_indices())
                  {
                    const double r = axial_distance(face->vertex(v));
                    rmin           = std::min(rmin, r);
                    rmax           = std::max(rmax, r);
                  }
                if (rmax - rmin <= 1e-6 * rmax)
                  {
                    face->set_all_manifold_ids(id);
                    any = true;
                  }
              }
        if (any)
          {
            if constexpr (dim == 2)
              tria.set_manifold(id, SphericalManifold<2>(Point<2>()));
            else
              tria.set_manifold(id, CylindricalManifold<3>(2));
          }
      }
  }

  template <int dim>
  std::set<types::boundary_id> coarse_boundary_ids(const Triangulation<dim> &tria)
  {
    std::set<types::boundary_id> ids;
    for (const auto &cell : tria.cell_iterators_on_level(0))
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          ids.insert(face->boundary_id());
    return ids;
  }

  template void generate_tunnel_mesh<2>(Triangulation<2> &,
                                        const GeneratedMeshSettings &);
  template void generate_tunnel_mesh<3>(Triangulation<3> &,
                                        const GeneratedMeshSettings &);
  template void read_gmsh_mesh<2>(Triangulation<2> &, const std::string &);
  template void read_gmsh_mesh<3>(Triangulation<3> &, const std::string &);
  template std::set<types::boundary_id> coarse_boundary_ids<2>(const Triangulation<2> &);
  template std::set<types::boundary_id> coarse_boundary_ids<3>(const Triangulation<3> &);
} // namespace demfem::fem
