// Flexible Voronoi particle model (dem/voronoi/flexible_model.h).
#include "dem/voronoi/flexible_model.h"

#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace demfem::dem::voronoi
{
  FlexibleVoronoiModel::FlexibleVoronoiModel(
      const Tessellation &tess, const std::vector<double> &px,
      const std::vector<double> &py, const std::vector<double> &radius,
      const GrainElasticity &grain_material, const ContactMaterial &contact_material,
      PointScheme scheme, const FlexibleMeshOptions &mesh_options)
      : mesh(tess, grain_material, mesh_options)
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
    // Contacts: one per shared edge (c < d); each point on the triangle of
    // each grain that holds its install position (the edge's fan triangle
    // of an unmerged cell; with merged vertices another one, or, for a
    // point just outside the coarsened cell, the nearest in the sense of
    // FlexibleGrainMesh::locate).
    for (int c = 0; c < n; ++c)
      for (int e = tess.begin(c); e < tess.end(c); ++e)
        {
          const int d = tess.edge_neighbour[e];
          if (d <= c)
            continue;
          if (tess.shared_edge(d, c) < 0)
            throw InputError("FlexibleVoronoiModel: cells " + std::to_string(c) +
                             " and " + std::to_string(d) +
                             " do not list their shared edge both ways");
          const int f = tess.next(c, e);
          const int k = contacts.add_contact(
              c, d, px[c], py[c], radius[c], px[d], py[d], radius[d], tess.vertex_x[e],
              tess.vertex_y[e], tess.vertex_x[f], tess.vertex_y[f], scheme);
          double xr, yr, nx, ny;
          contacts.reference_frame(
              k, GrainKinematics{px.data(), py.data(), radius.data()}, xr, yr, nx, ny);
          for (int p = contacts.point_offset[k]; p < contacts.point_offset[k + 1]; ++p)
            {
              const double X = xr - contacts.s[p] * ny, Y = yr + contacts.s[p] * nx;
              triangle_a.push_back(mesh.locate(c, mesh.x0.data(), mesh.y0.data(), X, Y));
              triangle_b.push_back(mesh.locate(d, mesh.x0.data(), mesh.y0.data(), X, Y));
            }
        }
    const int np = contacts.n_points();
    point_fx.assign(np, 0.0);
    point_fy.assign(np, 0.0);
    point_N.assign(6 * np, 0.0);
    n_installed_contacts = contacts.n_contacts();
    search.reset(n);
    for (int k = 0; k < n_installed_contacts; ++k)
      search.add_contact(contacts.grain_a[k], contacts.grain_b[k]);
    // Disks that overlap at install without a shared edge (docs/voronoi.md,
    // "New contacts"): their contacts start stress free, as the installed
    // ones do.
    update_disk_centres();
    rebuild_verlet_list();
    form_new_contacts(true, 0.0);
    build_gather_lists();
    for (int c = 0; c < n; ++c)
      for (int e = tess.begin(c); e < tess.end(c); ++e)
        if (tess.edge_neighbour[e] == Tessellation::boundary)
          outline_edges.push_back(boundary_edge(tess, c, e, px[c], py[c]));
    double xmin, ymin, xmax, ymax;
    for (const SideEdge &s : rectangle_side_edges(tess, xmin, ymin, xmax, ymax))
      {
        BoundaryEdge b = boundary_edge(tess, s.cell, s.edge, px[s.cell], py[s.cell]);
        b.side         = s.side;
        boundary_edges.push_back(b);
      }
  }

  void FlexibleVoronoiModel::build_gather_lists()
  {
    // Each node's contributions in ascending (point, slot): the gather
    // order, hence the sums, do not depend on the thread count.
    const int np = contacts.n_points();
    node_point_offset.assign(mesh.n_nodes() + 1, 0);
    for (int p = 0; p < np; ++p)
      for (int i = 0; i < 3; ++i)
        {
          ++node_point_offset[mesh.triangle_nodes[3 * triangle_a[p] + i] + 1];
          ++node_point_offset[mesh.triangle_nodes[3 * triangle_b[p] + i] + 1];
        }
    for (int m = 0; m < mesh.n_nodes(); ++m)
      node_point_offset[m + 1] += node_point_offset[m];
    node_point.resize(node_point_offset.back());
    {
      std::vector<int> fill(node_point_offset.begin(), node_point_offset.end() - 1);
      for (int p = 0; p < np; ++p)
        for (int i = 0; i < 6; ++i)
          {
            const int t = i < 3 ? triangle_a[p] : triangle_b[p];
            node_point[fill[mesh.triangle_nodes[3 * t + i % 3]]++] = 6 * p + i;
          }
    }
  }

  FlexibleVoronoiModel::BoundaryEdge FlexibleVoronoiModel::boundary_edge(
      const Tessellation &tess, int c, int e, double pcx, double pcy) const
  {
    const int    f = tess.next(c, e);
    BoundaryEdge b;
    b.grain  = c;
    b.length = tess.edge_length[e];
    b.end[0] = mesh.stencil(c, tess.vertex_x[e], tess.vertex_y[e]);
    b.end[1] = mesh.stencil(c, tess.vertex_x[f], tess.vertex_y[f]);
    // Outward normal of a counter-clockwise edge: (d_y, -d_x) / L.
    const double dx = tess.vertex_x[f] - tess.vertex_x[e];
    const double dy = tess.vertex_y[f] - tess.vertex_y[e];
    b.h = ((tess.vertex_x[e] - pcx) * dy - (tess.vertex_y[e] - pcy) * dx) / b.length;
    return b;
  }

  int FlexibleVoronoiModel::add_platen(Side side, PlatenLaw law, double friction)
  {
    const ContactMaterial &cm = contacts.contact_material();
    Platen                 p  = make_platen(side, law, friction);
    p.point_begin             = static_cast<int>(pp_stencil.size());
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
          // The point w0 end0 + (1 - w0) end1 of the install edge.
          const double X =
              w0 * e.end[0].x(mesh.x0.data()) + (1 - w0) * e.end[1].x(mesh.x0.data());
          const double Y =
              w0 * e.end[0].x(mesh.y0.data()) + (1 - w0) * e.end[1].x(mesh.y0.data());
          pp_stencil.push_back(w0 == 1   ? e.end[0]
                                       : w0 == 0 ? e.end[1]
                                                 : mesh.stencil(e.grain, X, Y));
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
    p.point_end = static_cast<int>(pp_stencil.size());
    for (auto *v : {&pp_un, &pp_wn, &pp_fs, &pp_dt, &pp_ds, &pp_fn})
      v->resize(pp_stencil.size(), 0.0);
    platens.push_back(p);
    return static_cast<int>(platens.size()) - 1;
  }

  int FlexibleVoronoiModel::add_disk_platen(Side side, double friction,
                                            double cone_degrees)
  {
    check_range("FlexibleVoronoiModel disk platen", "cone_degrees", cone_degrees, 0, 90,
                true, false);
    const ContactMaterial &cm = contacts.contact_material();
    Platen                 p  = make_platen(side, PlatenLaw::frictional, friction);
    p.gap                     = true;
    p.friction                = friction;
    p.point_begin             = static_cast<int>(pp_stencil.size());
    p.plane                   = -HUGE_VAL;
    const double  cos_cone    = std::cos(cone_degrees * M_PI / 180);
    const double *X0 = mesh.x0.data(), *Y0 = mesh.y0.data();
    for (const auto &e : outline_edges)
      {
        const double ax = e.end[0].x(X0), ay = e.end[0].x(Y0);
        const double bx = e.end[1].x(X0), by = e.end[1].x(Y0);
        // Outward normal of a counter-clockwise edge: (d_y, -d_x) / L; the
        // rigid model's selection and stiffness (kn = E_c / h).
        if (((by - ay) * p.nx - (bx - ax) * p.ny) / e.length < cos_cone)
          continue;
        const double kn  = cm.deformability_mode() ? cm.contact_modulus / e.h : cm.kn;
        const double A   = e.length * cm.thickness;
        auto         add = [&](const PointStencil &s, double a) {
          pp_stencil.push_back(s);
          pp_area.push_back(a);
          pp_kn.push_back(kn);
          pp_ks.push_back(kn / cm.kratio);
          pp_crack.push_back(PointCrack::unbonded);
          p.plane = std::max(p.plane, s.x(X0) * p.nx + s.x(Y0) * p.ny);
        };
        add(e.end[0], A / 6);
        add(mesh.stencil(e.grain, 0.5 * (ax + bx), 0.5 * (ay + by)), 2 * A / 3);
        add(e.end[1], A / 6);
      }
    p.point_end = static_cast<int>(pp_stencil.size());
    if (p.point_end == p.point_begin)
      throw InputError("FlexibleVoronoiModel: no outline edge faces the disk platen");
    for (auto *v : {&pp_un, &pp_wn, &pp_fs, &pp_dt, &pp_ds, &pp_fn})
      v->resize(pp_stencil.size(), 0.0);
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
    // Adds (Fx, Fy) at a point carried by the nodes: f_m = w_m F.
    auto add = [&](const PointStencil &s, double Fx, double Fy) {
      for (int i = 0; i < 3; ++i)
        {
          fx[s.node[i]] += s.w[i] * Fx;
          fy[s.node[i]] += s.w[i] * Fy;
        }
    };
    for (const auto &e : boundary_edges)
      {
        const double p = pressure[static_cast<int>(e.side)];
        if (p == 0)
          continue;
        // -p t L n_out on the current edge, n_out L = (d_y, -d_x); half to
        // each end (the consistent load of a linear edge).
        const double dx = point_x(e.end[1]) - point_x(e.end[0]);
        const double dy = point_y(e.end[1]) - point_y(e.end[0]);
        add(e.end[0], -0.5 * p * t * dy, 0.5 * p * t * dx);
        add(e.end[1], -0.5 * p * t * dy, 0.5 * p * t * dx);
      }
    for (auto &p : platens)
      {
        p.fx = p.fy = 0;
        if (!p.active)
          continue;
        const double nx = p.nx, ny = p.ny, tx = -ny, ty = nx;
        const double plane = p.plane + p.ux * nx + p.uy * ny;
        for (int i = p.point_begin; i < p.point_end; ++i)
          {
            const PointStencil &s = pp_stencil[i];
            // Platen (B) relative to the point (A).
            const double vrx  = p.vx - s.x(vx.data());
            const double vry  = p.vy - s.x(vy.data());
            const double d_us = (vrx * tx + vry * ty) * dt;
            const double f_n =
                p.gap ? update_gap_point(p, pp_kn[i], pp_ks[i], pp_area[i],
                                         point_x(s) * nx + point_y(s) * ny - plane, d_us,
                                         pp_fs[i])
                      : update_platen_point(p, pp_kn[i], pp_ks[i], pp_area[i],
                                            (vrx * nx + vry * ny) * dt, d_us,
                                            PointState{pp_un[i], pp_wn[i], pp_fs[i],
                                                       pp_dt[i], pp_ds[i], pp_crack[i]});
            pp_fn[i]        = f_n;
            const double Fx = -f_n * nx + pp_fs[i] * tx, Fy = -f_n * ny + pp_fs[i] * ty;
            p.fx += Fx;
            p.fy += Fy;
            add(s, -Fx, -Fy);
          }
      }
  }

  double FlexibleVoronoiModel::side_displacement(Side side, int component) const
  {
    const auto &u   = component == 0 ? x : y;
    const auto &u0  = component == 0 ? mesh.x0 : mesh.y0;
    double      sum = 0, weight = 0;
    for (const auto &e : boundary_edges)
      if (e.side == side)
        for (const PointStencil &s : e.end)
          {
            sum += 0.5 * e.length * (s.x(u.data()) - s.x(u0.data()));
            weight += 0.5 * e.length;
          }
    return weight > 0 ? sum / weight : 0.0;
  }

  double FlexibleVoronoiModel::side_position(Side side, int component) const
  {
    const auto &u0  = component == 0 ? mesh.x0 : mesh.y0;
    double      sum = 0, weight = 0;
    for (const auto &e : boundary_edges)
      if (e.side == side)
        for (const PointStencil &s : e.end)
          {
            sum += 0.5 * e.length * s.x(u0.data());
            weight += 0.5 * e.length;
          }
    return weight > 0 ? sum / weight : 0.0;
  }

  void FlexibleVoronoiModel::update_contact_points(double dt)
  {
    const int nc = contacts.n_contacts();
    // Each contact writes only its own points' state and slots.
#pragma omp parallel for schedule(static) if (n_grains() >= parallel_threshold)
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
            double      *Na = &point_N[6 * p], *Nb = Na + 3;
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
            contacts.fn[p] = f_n;
            point_fx[p]    = -f_n * nx + contacts.fs[p] * tx;
            point_fy[p]    = -f_n * ny + contacts.fs[p] * ty;
          }
      }
  }

  void FlexibleVoronoiModel::compute_forces(double dt)
  {
    detect_new_contacts(dt);
    update_contact_points(dt);
    const int     ng = n_grains();
    const double *X = x.data(), *Y = y.data();
    // Per grain: applied + internal forces of its triangles + its nodes'
    // contact contributions in point order (f_m = -N_m f on A, N_m f on B).
#pragma omp parallel for schedule(static) if (ng >= parallel_threshold)
    for (int c = 0; c < ng; ++c)
      {
        const int m0 = mesh.grain_node_offset[c], m1 = mesh.grain_node_offset[c + 1];
        for (int m = m0; m < m1; ++m)
          {
            fx[m] = fx_ext[m];
            fy[m] = fy_ext[m];
          }
        mesh.add_grain_internal_forces(c, X, Y, fx.data(), fy.data());
        for (int m = m0; m < m1; ++m)
          for (int q = node_point_offset[m]; q < node_point_offset[m + 1]; ++q)
            {
              const int    j = node_point[q], p = j / 6;
              const double w = j % 6 < 3 ? -point_N[j] : point_N[j];
              fx[m] += w * point_fx[p];
              fy[m] += w * point_fy[p];
            }
      }
    add_boundary_forces(dt);
  }

  void FlexibleVoronoiModel::step(double dt)
  {
    const int nn = mesh.n_nodes();
    compute_forces(dt);
    const double alpha = damping;
    auto         sign  = [](double v) { return v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0; };
#pragma omp parallel for schedule(static) if (n_grains() >= parallel_threshold)
    for (int m = 0; m < nn; ++m)
      {
        if (fixed[m])
          {
            vx[m] = vy[m] = 0;
            continue;
          }
        const double Fx = fx[m] - alpha * std::abs(fx[m]) * sign(vx[m]);
        const double Fy = fy[m] - alpha * std::abs(fy[m]) * sign(vy[m]);
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
    // A point's spring acts on the nodes that carry it; the lightest of
    // them gives the bound 2 sqrt(m / k) (a node with weight 0 does not
    // feel it: the far node of an edge point).
    auto bound = [&](int node, double w, double k) {
      if (w > 1e-9)
        dt = std::min(dt, 2 * std::sqrt(mesh.mass[node] / k));
    };
    for (int c = 0; c < contacts.n_contacts(); ++c)
      {
        const auto  &k    = contacts.coefficients(c);
        const double kmax = std::max(k.kn, k.ks);
        for (int p = contacts.point_offset[c]; p < contacts.point_offset[c + 1]; ++p)
          for (int t : {triangle_a[p], triangle_b[p]})
            for (int i = 0; i < 3; ++i)
              bound(mesh.triangle_nodes[3 * t + i], 1.0, kmax * contacts.area[p]);
      }
    for (std::size_t i = 0; i < pp_stencil.size(); ++i)
      for (int j = 0; j < 3; ++j)
        bound(pp_stencil[i].node[j], std::abs(pp_stencil[i].w[j]),
              std::max(pp_kn[i], pp_ks[i]) * pp_area[i]);
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
