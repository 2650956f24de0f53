// Flexible Voronoi particle model (dem/voronoi/flexible_model.h).
#include "dem/voronoi/flexible_model.h"

#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace demfem::dem::voronoi
{
  FlexibleVoronoiModel::FlexibleVoronoiModel(const Tessellation        &tess,
                                             const std::vector<double> &px,
                                             const std::vector<double> &py,
                                             const std::vector<double> &radius,
                                             const GrainElasticity     &grain_material,
                                             const ContactMaterial     &contact_material,
                                             PointScheme                scheme)
      : mesh(tess, grain_material)
      , contacts(contact_material)
  {
    const int n = tess.n_cells();
    if ((int)px.size() != n || py.size() != px.size() || radius.size() != px.size())
      throw InputError("FlexibleVoronoiModel: the packing has " +
                       std::to_string(px.size()) + " disks, the tessellation " +
                       std::to_string(n) + " cells");
    x = mesh.x0;
    y = mesh.y0;
    vx.assign(mesh.n_nodes(), 0.0);
    vy     = vx;
    fx     = vx;
    fy     = vx;
    fx_ext = vx;
    fy_ext = vx;
    fixed.assign(mesh.n_nodes(), 0);
    disk_dx.assign(n, 0.0);
    disk_dy.assign(n, 0.0);
    disk_radius = radius;
    for (int c = 0; c < n; ++c)
      {
        disk_dx[c] = px[c] - tess.centroid_x[c];
        disk_dy[c] = py[c] - tess.centroid_y[c];
      }
    // Contacts: one per shared edge (c < d); the points lie on the fan
    // triangle of each grain that holds the edge (triangle j of a cell is
    // (centroid, v_j, v_j+1), i.e. edge j).
    for (int c = 0; c < n; ++c)
      for (int e = tess.begin(c); e < tess.end(c); ++e)
        {
          const int d = tess.edge_neighbour[e];
          if (d <= c)
            continue;
          const int g = tess.shared_edge(d, c);
          if (g < 0)
            throw InputError("FlexibleVoronoiModel: cells " + std::to_string(c) +
                             " and " + std::to_string(d) +
                             " do not list their shared edge both ways");
          const int f = tess.next(c, e);
          contacts.add_contact(c, d, px[c], py[c], radius[c], px[d], py[d], radius[d],
                               tess.vertex_x[e], tess.vertex_y[e], tess.vertex_x[f],
                               tess.vertex_y[f], scheme);
          const int ta = mesh.grain_triangle_offset[c] + (e - tess.begin(c));
          const int tb = mesh.grain_triangle_offset[d] + (g - tess.begin(d));
          triangle_a.resize(contacts.n_points(), ta);
          triangle_b.resize(contacts.n_points(), tb);
        }
  }

  void FlexibleVoronoiModel::add_contact_forces(double dt)
  {
    const int nc = contacts.n_contacts();
    for (int c = 0; c < nc; ++c)
      {
        const int    a = contacts.grain_a[c], b = contacts.grain_b[c];
        const double xa = disk_x(a), ya = disk_y(a), xb = disk_x(b), yb = disk_y(b);
        const double dist = std::hypot(xb - xa, yb - ya);
        const double nx = (xb - xa) / dist, ny = (yb - ya) / dist, tx = -ny, ty = nx;
        const double U  = disk_radius[a] + disk_radius[b] - dist;
        const double ra = disk_radius[a] - U / 2 + contacts.offset[c];
        const double xr = xa + ra * nx, yr = ya + ra * ny;
        const auto  &k = contacts.coefficients(c);
        for (int p = contacts.point_offset[c]; p < contacts.point_offset[c + 1]; ++p)
          {
            const double px = xr + contacts.s[p] * tx, py = yr + contacts.s[p] * ty;
            double       Na[3], Nb[3];
            mesh.shape_functions(triangle_a[p], x.data(), y.data(), px, py, Na);
            mesh.shape_functions(triangle_b[p], x.data(), y.data(), px, py, Nb);
            const int *na  = &mesh.triangle_nodes[3 * triangle_a[p]];
            const int *nb  = &mesh.triangle_nodes[3 * triangle_b[p]];
            double     vrx = 0, vry = 0;
            for (int i = 0; i < 3; ++i)
              {
                vrx += Nb[i] * vx[nb[i]] - Na[i] * vx[na[i]];
                vry += Nb[i] * vy[nb[i]] - Na[i] * vy[na[i]];
              }
            const double f_n =
                update_point(k, contacts.area[p], (vrx * nx + vry * ny) * dt,
                             (vrx * tx + vry * ty) * dt,
                             PointState{contacts.un[p], contacts.wn[p], contacts.fs[p],
                                        contacts.damage_t[p], contacts.damage_s[p],
                                        contacts.crack[p]});
            contacts.fn[p]  = f_n;
            const double Fx = -f_n * nx + contacts.fs[p] * tx;
            const double Fy = -f_n * ny + contacts.fs[p] * ty;
            for (int i = 0; i < 3; ++i)
              {
                fx[nb[i]] += Nb[i] * Fx;
                fy[nb[i]] += Nb[i] * Fy;
                fx[na[i]] -= Na[i] * Fx;
                fy[na[i]] -= Na[i] * Fy;
              }
          }
      }
  }

  void FlexibleVoronoiModel::compute_forces(double dt)
  {
    std::copy(fx_ext.begin(), fx_ext.end(), fx.begin());
    std::copy(fy_ext.begin(), fy_ext.end(), fy.begin());
    mesh.add_internal_forces(x.data(), y.data(), fx.data(), fy.data());
    add_contact_forces(dt);
  }

  void FlexibleVoronoiModel::step(double dt)
  {
    const int nn = mesh.n_nodes();
    compute_forces(dt);
    auto sign = [](double v) { return v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0; };
    for (int m = 0; m < nn; ++m)
      {
        if (fixed[m])
          {
            vx[m] = vy[m] = 0;
            continue;
          }
        const double Fx = fx[m] - damping * std::abs(fx[m]) * sign(vx[m]);
        const double Fy = fy[m] - damping * std::abs(fy[m]) * sign(vy[m]);
        vx[m] += dt * Fx / mesh.mass[m];
        vy[m] += dt * Fy / mesh.mass[m];
        x[m] += dt * vx[m];
        y[m] += dt * vy[m];
      }
  }

  double FlexibleVoronoiModel::stable_time_step(double safety) const
  {
    double dt = mesh.critical_time_step();
    // A contact point's spring acts on the nodes of its triangles; the
    // lightest node of each gives the bound 2 sqrt(m / k).
    for (int c = 0; c < contacts.n_contacts(); ++c)
      {
        const auto  &k    = contacts.coefficients(c);
        const double kmax = std::max(k.kn, k.ks);
        for (int p = contacts.point_offset[c]; p < contacts.point_offset[c + 1]; ++p)
          for (int t : {triangle_a[p], triangle_b[p]})
            for (int i = 0; i < 3; ++i)
              {
                const double m = mesh.mass[mesh.triangle_nodes[3 * t + i]];
                dt = std::min(dt, 2 * std::sqrt(m / (kmax * contacts.area[p])));
              }
      }
    return safety * dt;
  }

  double FlexibleVoronoiModel::kinetic_energy() const
  {
    double e = 0;
    for (int m = 0; m < mesh.n_nodes(); ++m)
      e += 0.5 * mesh.mass[m] * (vx[m] * vx[m] + vy[m] * vy[m]);
    return e;
  }
} // namespace demfem::dem::voronoi
