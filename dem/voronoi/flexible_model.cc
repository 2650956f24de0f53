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
      , scheme(scheme)
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
    // Side edges: edge j of a cell joins its nodes 1 + j and 1 + (j + 1) % k.
    double xmin, ymin, xmax, ymax;
    for (const SideEdge &s : rectangle_side_edges(tess, xmin, ymin, xmax, ymax))
      {
        const int c = s.cell, k = tess.end(c) - tess.begin(c), j = s.edge - tess.begin(c);
        BoundaryEdge e;
        e.grain  = c;
        e.side   = s.side;
        e.node0  = mesh.grain_node_offset[c] + 1 + j;
        e.node1  = mesh.grain_node_offset[c] + 1 + (j + 1) % k;
        e.length = tess.edge_length[s.edge];
        // Outward normal of a counter-clockwise edge: (d_y, -d_x) / L.
        const double dx = mesh.x0[e.node1] - mesh.x0[e.node0];
        const double dy = mesh.y0[e.node1] - mesh.y0[e.node0];
        e.h = ((mesh.x0[e.node0] - px[c]) * dy - (mesh.y0[e.node0] - py[c]) * dx) /
              e.length;
        boundary_edges.push_back(e);
      }
  }

  int FlexibleVoronoiModel::add_platen(Side side, PlatenLaw law, double friction)
  {
    const ContactMaterial &cm = contacts.contact_material();
    Platen                 p  = make_platen(side, law, friction);
    p.point_begin             = static_cast<int>(pp_node0.size());
    for (const auto &e : boundary_edges)
      {
        if (e.side != side)
          continue;
        if (!(e.h > 0))
          throw InputError("FlexibleVoronoiModel: a disk centre lies on or beyond the "
                           "platen side (grain " +
                           std::to_string(e.grain) + ")");
        // As the rigid model (dem/voronoi/rigid_model.h): kn = E_c / h in the
        // deformability mode.
        const double kn  = cm.deformability_mode() ? cm.contact_modulus / e.h : cm.kn;
        const double A   = e.length * cm.thickness;
        auto         add = [&](double w0, double a) {
          pp_node0.push_back(e.node0);
          pp_node1.push_back(e.node1);
          pp_w0.push_back(w0);
          pp_area.push_back(a);
          pp_kn.push_back(kn);
          pp_ks.push_back(kn / cm.kratio);
          pp_crack.push_back(law == PlatenLaw::frictional ? PointCrack::unbonded
                                                                  : PointCrack::intact);
        };
        if (scheme == PointScheme::lobatto3)
          {
            add(1.0, A / 6);
            add(0.5, 2 * A / 3);
            add(0.0, A / 6);
          }
        else
          add(0.5, A);
      }
    p.point_end = static_cast<int>(pp_node0.size());
    for (auto *v : {&pp_un, &pp_wn, &pp_fs, &pp_dt, &pp_ds, &pp_fn})
      v->resize(pp_node0.size(), 0.0);
    platens.push_back(p);
    return static_cast<int>(platens.size()) - 1;
  }

  void FlexibleVoronoiModel::activate_platen(int k)
  {
    Platen &p = platens.at(k);
    p.active  = true;
    for (int i = p.point_begin; i < p.point_end; ++i)
      pp_un[i] = pp_wn[i] = pp_fs[i] = pp_dt[i] = pp_ds[i] = pp_fn[i] = 0;
  }

  void FlexibleVoronoiModel::add_boundary_forces(double dt)
  {
    const double t = contacts.thickness();
    for (const auto &e : boundary_edges)
      {
        const double p = pressure[static_cast<int>(e.side)];
        if (p == 0)
          continue;
        // -p t L n_out on the current edge, n_out L = (d_y, -d_x); half to
        // each node (the consistent load of a linear edge).
        const double dx = x[e.node1] - x[e.node0], dy = y[e.node1] - y[e.node0];
        fx[e.node0] -= 0.5 * p * t * dy;
        fy[e.node0] += 0.5 * p * t * dx;
        fx[e.node1] -= 0.5 * p * t * dy;
        fy[e.node1] += 0.5 * p * t * dx;
      }
    for (auto &p : platens)
      {
        p.fx = p.fy = 0;
        if (!p.active)
          continue;
        const double nx = p.nx, ny = p.ny, tx = -ny, ty = nx;
        for (int i = p.point_begin; i < p.point_end; ++i)
          {
            const int    a = pp_node0[i], b = pp_node1[i];
            const double w = pp_w0[i];
            // Platen (B) relative to the edge point (A).
            const double vrx = p.vx - (w * vx[a] + (1 - w) * vx[b]);
            const double vry = p.vy - (w * vy[a] + (1 - w) * vy[b]);
            const double f_n = update_platen_point(
                p, pp_kn[i], pp_ks[i], pp_area[i], (vrx * nx + vry * ny) * dt,
                (vrx * tx + vry * ty) * dt,
                PointState{pp_un[i], pp_wn[i], pp_fs[i], pp_dt[i], pp_ds[i],
                           pp_crack[i]});
            pp_fn[i]        = f_n;
            const double Fx = -f_n * nx + pp_fs[i] * tx, Fy = -f_n * ny + pp_fs[i] * ty;
            p.fx += Fx;
            p.fy += Fy;
            fx[a] -= w * Fx;
            fy[a] -= w * Fy;
            fx[b] -= (1 - w) * Fx;
            fy[b] -= (1 - w) * Fy;
          }
      }
  }

  double FlexibleVoronoiModel::side_displacement(Side side, int component) const
  {
    double sum = 0, weight = 0;
    for (const auto &e : boundary_edges)
      if (e.side == side)
        for (int n : {e.node0, e.node1})
          {
            sum +=
                0.5 * e.length * (component == 0 ? x[n] - mesh.x0[n] : y[n] - mesh.y0[n]);
            weight += 0.5 * e.length;
          }
    return weight > 0 ? sum / weight : 0.0;
  }

  double FlexibleVoronoiModel::side_position(Side side, int component) const
  {
    double sum = 0, weight = 0;
    for (const auto &e : boundary_edges)
      if (e.side == side)
        for (int n : {e.node0, e.node1})
          {
            sum += 0.5 * e.length * (component == 0 ? mesh.x0[n] : mesh.y0[n]);
            weight += 0.5 * e.length;
          }
    return weight > 0 ? sum / weight : 0.0;
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
    add_boundary_forces(dt);
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
    for (auto &p : platens)
      {
        p.ux += dt * p.vx;
        p.uy += dt * p.vy;
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
    for (std::size_t i = 0; i < pp_node0.size(); ++i)
      for (int n : {pp_node0[i], pp_node1[i]})
        dt = std::min(dt, 2 * std::sqrt(mesh.mass[n] /
                                        (std::max(pp_kn[i], pp_ks[i]) * pp_area[i])));
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
