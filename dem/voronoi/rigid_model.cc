// Rigid Voronoi particle model (dem/voronoi/rigid_model.h).
#include "dem/voronoi/rigid_model.h"

#include "dem/engine/types.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace demfem::dem::voronoi
{
  double polygon_polar_moment(const double *vx, const double *vy, int n, double px,
                              double py)
  {
    // Sum over the triangles (p, v_k, v_k+1) of the exact polygon formula
    // (1/12) sum cross_k (x_k^2 + x_k x_k+1 + x_k+1^2 + y_k^2 + ...), with
    // coordinates relative to p so no digits are lost to the position.
    double J = 0;
    for (int k = 0; k < n; ++k)
      {
        const int    l  = (k + 1) % n;
        const double x0 = vx[k] - px, y0 = vy[k] - py, x1 = vx[l] - px, y1 = vy[l] - py;
        const double cr = x0 * y1 - x1 * y0;
        J += cr * (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1);
      }
    return J / 12;
  }

  RigidVoronoiModel::RigidVoronoiModel(const Tessellation        &tess,
                                       const std::vector<double> &px,
                                       const std::vector<double> &py,
                                       const std::vector<double> &r, double density,
                                       const ContactMaterial &contact_material,
                                       PointScheme            scheme)
      : x(px)
      , y(py)
      , x0(px)
      , y0(py)
      , radius(r)
      , contacts(contact_material)
      , scheme(scheme)
  {
    const int n = tess.n_cells();
    if ((int)px.size() != n || py.size() != px.size() || r.size() != px.size())
      throw InputError("RigidVoronoiModel: the packing has " + std::to_string(px.size()) +
                       " disks, the tessellation " + std::to_string(n) + " cells");
    check_range("RigidVoronoiModel", "density", density, 0, HUGE_VAL, true, true);
    theta.assign(n, 0.0);
    vx      = theta;
    vy      = theta;
    omega   = theta;
    fx      = theta;
    fy      = theta;
    mz      = theta;
    fx_ext  = theta;
    fy_ext  = theta;
    mz_ext  = theta;
    mass    = theta;
    inertia = theta;
    held.assign(n, 0);
    const double t = contact_material.thickness;
    for (int c = 0; c < n; ++c)
      {
        const int k = tess.end(c) - tess.begin(c);
        if (tess.empty_reason[c] != EmptyCellReason::none || k < 3)
          {
            held[c] = 1;
            continue;
          }
        mass[c]    = density * t * tess.area[c];
        inertia[c] = density * t *
                     polygon_polar_moment(&tess.vertex_x[tess.begin(c)],
                                          &tess.vertex_y[tess.begin(c)], k, px[c], py[c]);
      }
    contacts.add_from_tessellation(tess, px, py, r, scheme);
    n_installed_contacts = contacts.n_contacts();
    // Cell polygons for the nearest-edge selection of new contacts.
    has_cell.assign(n, 0);
    cell_offset.assign(1, 0);
    for (int c = 0; c < n; ++c)
      {
        has_cell[c] = !held[c];
        if (has_cell[c])
          for (int e = tess.begin(c); e < tess.end(c); ++e)
            {
              cell_rx.push_back(tess.vertex_x[e] - px[c]);
              cell_ry.push_back(tess.vertex_y[e] - py[c]);
            }
        cell_offset.push_back(static_cast<int>(cell_rx.size()));
      }
    search.reset(n);
    for (int k = 0; k < n_installed_contacts; ++k)
      search.add_contact(contacts.grain_a[k], contacts.grain_b[k]);
    // Disks that overlap at install without a shared edge (docs/voronoi.md,
    // "New contacts"): their contacts start stress free, as the installed
    // ones do.
    rebuild_verlet_list();
    form_new_contacts(true, 0.0);
    build_grain_contact_lists();

    for (int c = 0; c < n; ++c)
      for (int e = tess.begin(c); e < tess.end(c); ++e)
        if (tess.edge_neighbour[e] == Tessellation::boundary)
          {
            const int    f = tess.next(c, e);
            BoundaryEdge edge;
            edge.grain  = c;
            edge.rx0    = tess.vertex_x[e] - px[c];
            edge.ry0    = tess.vertex_y[e] - py[c];
            edge.rx1    = tess.vertex_x[f] - px[c];
            edge.ry1    = tess.vertex_y[f] - py[c];
            edge.length = tess.edge_length[e];
            outline_edges.push_back(edge);
          }
    // Boundary edges of a rectangle (dem/voronoi/boundary.h).
    double xmin, ymin, xmax, ymax;
    for (const SideEdge &s : rectangle_side_edges(tess, xmin, ymin, xmax, ymax))
      {
        const int    f = tess.next(s.cell, s.edge);
        BoundaryEdge edge;
        edge.grain  = s.cell;
        edge.side   = s.side;
        edge.rx0    = tess.vertex_x[s.edge] - px[s.cell];
        edge.ry0    = tess.vertex_y[s.edge] - py[s.cell];
        edge.rx1    = tess.vertex_x[f] - px[s.cell];
        edge.ry1    = tess.vertex_y[f] - py[s.cell];
        edge.length = tess.edge_length[s.edge];
        boundary_edges.push_back(edge);
      }
  }

  void RigidVoronoiModel::build_grain_contact_lists()
  {
    const int n = n_grains();
    grain_contact_offset.assign(n + 1, 0);
    for (int c = 0; c < contacts.n_contacts(); ++c)
      {
        ++grain_contact_offset[contacts.grain_a[c] + 1];
        ++grain_contact_offset[contacts.grain_b[c] + 1];
      }
    for (int g = 0; g < n; ++g)
      grain_contact_offset[g + 1] += grain_contact_offset[g];
    grain_contact.resize(grain_contact_offset[n]);
    std::vector<int> fill(grain_contact_offset.begin(), grain_contact_offset.end() - 1);
    for (int c = 0; c < contacts.n_contacts(); ++c) // ascending c per grain
      {
        grain_contact[fill[contacts.grain_a[c]]++] = 2 * c;
        grain_contact[fill[contacts.grain_b[c]]++] = 2 * c + 1;
      }
  }

  int RigidVoronoiModel::add_platen(Side side, PlatenLaw law, double friction)
  {
    const ContactMaterial &cm = contacts.contact_material();
    Platen                 p  = make_platen(side, law, friction);
    p.point_begin             = static_cast<int>(pp_grain.size());
    const double tx = -p.ny, ty = p.nx; // t = k x n
    for (const auto &e : boundary_edges)
      {
        if (e.side != side)
          continue;
        const double mx = 0.5 * (e.rx0 + e.rx1), my = 0.5 * (e.ry0 + e.ry1);
        const double h = mx * p.nx + my * p.ny; // disk centre to edge line
        if (!(h > 0))
          throw InputError("RigidVoronoiModel: a disk centre lies on or beyond the "
                           "platen side (grain " +
                           std::to_string(e.grain) + ")");
        // Seed 004 §2.5 per unit area; deformability mode: the half spring
        // from the centre to the rigid platen, kn = E_c / h.
        const double kn  = cm.deformability_mode() ? cm.contact_modulus / h : cm.kn;
        const double A   = e.length * cm.thickness;
        auto         add = [&](double s, double a) {
          pp_grain.push_back(e.grain);
          pp_h.push_back(h);
          pp_s.push_back(s);
          pp_area.push_back(a);
          pp_kn.push_back(kn);
          pp_ks.push_back(kn / cm.kratio);
          pp_crack.push_back(law == PlatenLaw::frictional ? PointCrack::unbonded
                                                                  : PointCrack::intact);
        };
        const double s0 = e.rx0 * tx + e.ry0 * ty, s1 = e.rx1 * tx + e.ry1 * ty;
        if (scheme == PointScheme::lobatto3)
          {
            add(s0, A / 6);
            add(0.5 * (s0 + s1), 2 * A / 3);
            add(s1, A / 6);
          }
        else
          add(0.5 * (s0 + s1), A); // one point: the edge middle
      }
    p.point_end = static_cast<int>(pp_grain.size());
    for (auto *v : {&pp_un, &pp_wn, &pp_fs, &pp_dt, &pp_ds, &pp_fn, &pp_rx, &pp_ry})
      v->resize(pp_grain.size(), 0.0);
    platens.push_back(p);
    return static_cast<int>(platens.size()) - 1;
  }

  int RigidVoronoiModel::add_disk_platen(Side side, double friction, double cone_degrees)
  {
    check_range("RigidVoronoiModel disk platen", "cone_degrees", cone_degrees, 0, 90,
                true, false);
    const ContactMaterial &cm = contacts.contact_material();
    Platen                 p  = make_platen(side, PlatenLaw::frictional, friction);
    p.gap                     = true;
    p.friction                = friction;
    p.point_begin             = static_cast<int>(pp_grain.size());
    const double cos_cone     = std::cos(cone_degrees * M_PI / 180);
    p.plane                   = -HUGE_VAL;
    for (const auto &e : outline_edges)
      {
        const double dx = e.rx1 - e.rx0, dy = e.ry1 - e.ry0;
        // Outward normal of a counter-clockwise edge: (d_y, -d_x) / L.
        if ((dy * p.nx - dx * p.ny) / e.length < cos_cone)
          continue;
        const int    g = e.grain;
        const double h = (e.rx0 * dy - e.ry0 * dx) / e.length; // centre to edge line
        // As the rectangle platens: kn = E_c / h in the deformability mode.
        const double kn  = cm.deformability_mode() ? cm.contact_modulus / h : cm.kn;
        const double A   = e.length * cm.thickness;
        auto         add = [&](double rx, double ry, double a) {
          pp_grain.push_back(g);
          pp_rx.push_back(rx);
          pp_ry.push_back(ry);
          // Arm length for the time step estimate (h^2 + s^2 = |r|^2).
          pp_h.push_back(std::hypot(rx, ry));
          pp_s.push_back(0);
          pp_area.push_back(a);
          pp_kn.push_back(kn);
          pp_ks.push_back(kn / cm.kratio);
          pp_crack.push_back(PointCrack::unbonded);
          p.plane = std::max(p.plane, (x[g] + rx) * p.nx + (y[g] + ry) * p.ny);
        };
        add(e.rx0, e.ry0, A / 6);
        add(0.5 * (e.rx0 + e.rx1), 0.5 * (e.ry0 + e.ry1), 2 * A / 3);
        add(e.rx1, e.ry1, A / 6);
      }
    p.point_end = static_cast<int>(pp_grain.size());
    if (p.point_end == p.point_begin)
      throw InputError("RigidVoronoiModel: no outline edge faces the disk platen");
    for (auto *v : {&pp_un, &pp_wn, &pp_fs, &pp_dt, &pp_ds, &pp_fn})
      v->resize(pp_grain.size(), 0.0);
    platens.push_back(p);
    return static_cast<int>(platens.size()) - 1;
  }

  void RigidVoronoiModel::platen_point_arm(int k, int i, double &rx, double &ry) const
  {
    const Platen &p = platens[k];
    if (p.gap)
      {
        const int    g = pp_grain[i];
        const double c = std::cos(theta[g]), s = std::sin(theta[g]);
        rx = c * pp_rx[i] - s * pp_ry[i];
        ry = s * pp_rx[i] + c * pp_ry[i];
        return;
      }
    rx = pp_h[i] * p.nx - pp_s[i] * p.ny;
    ry = pp_h[i] * p.ny + pp_s[i] * p.nx;
  }

  void RigidVoronoiModel::activate_platen(int k)
  {
    Platen &p = platens.at(k);
    p.active  = true;
    for (int i = p.point_begin; i < p.point_end; ++i)
      pp_un[i] = pp_wn[i] = pp_fs[i] = pp_dt[i] = pp_ds[i] = pp_fn[i] = 0;
  }

  void RigidVoronoiModel::pressure_force(const BoundaryEdge &e, double &Fx, double &Fy,
                                         double &rx, double &ry) const
  {
    const double p = pressure[static_cast<int>(e.side)];
    const int    g = e.grain;
    const double c = std::cos(theta[g]), s = std::sin(theta[g]);
    const double ax = c * e.rx0 - s * e.ry0, ay = s * e.rx0 + c * e.ry0;
    const double bx = c * e.rx1 - s * e.ry1, by = s * e.rx1 + c * e.ry1;
    // Counter-clockwise cell: outward normal (d_y, -d_x) / L of the current
    // edge d = b - a; the traction p pushes inward: force -p t L n_out =
    // -p t (d_y, -d_x), at the middle of the edge.
    const double t = contacts.thickness();
    Fx             = -p * t * (by - ay);
    Fy             = p * t * (bx - ax);
    rx             = 0.5 * (ax + bx);
    ry             = 0.5 * (ay + by);
  }

  void RigidVoronoiModel::add_pressure_forces()
  {
    for (const auto &e : boundary_edges)
      {
        if (pressure[static_cast<int>(e.side)] == 0)
          continue;
        double Fx, Fy, rx, ry;
        pressure_force(e, Fx, Fy, rx, ry);
        fx[e.grain] += Fx;
        fy[e.grain] += Fy;
        mz[e.grain] += rx * Fy - ry * Fx;
      }
  }

  void RigidVoronoiModel::add_platen_forces(double dt)
  {
    for (int k = 0; k < static_cast<int>(platens.size()); ++k)
      {
        Platen &p = platens[k];
        p.fx = p.fy = 0;
        if (!p.active)
          continue;
        const double nx = p.nx, ny = p.ny, tx = -ny, ty = nx;
        const double plane = p.plane + p.ux * nx + p.uy * ny;
        for (int i = p.point_begin; i < p.point_end; ++i)
          {
            const int g = pp_grain[i];
            double    rx, ry;
            platen_point_arm(k, i, rx, ry);
            // Velocity of the platen (B) relative to the grain (A) at the point.
            const double vrx  = p.vx - (vx[g] - omega[g] * ry);
            const double vry  = p.vy - (vy[g] + omega[g] * rx);
            const double d_us = (vrx * tx + vry * ty) * dt;
            double       f_n;
            if (p.gap) // penetration of the plane; Coulomb shear while in touch
              f_n = update_gap_point(p, pp_kn[i], pp_ks[i], pp_area[i],
                                     (x[g] + rx) * nx + (y[g] + ry) * ny - plane, d_us,
                                     pp_fs[i]);
            else
              f_n = update_platen_point(p, pp_kn[i], pp_ks[i], pp_area[i],
                                        (vrx * nx + vry * ny) * dt, d_us,
                                        PointState{pp_un[i], pp_wn[i], pp_fs[i], pp_dt[i],
                                                   pp_ds[i], pp_crack[i]});
            pp_fn[i] = f_n;
            // Point force on the platen -F_n n + F_s t, the opposite on the grain.
            const double Fx = -f_n * nx + pp_fs[i] * tx, Fy = -f_n * ny + pp_fs[i] * ty;
            p.fx += Fx;
            p.fy += Fy;
            fx[g] -= Fx;
            fy[g] -= Fy;
            mz[g] -= rx * Fy - ry * Fx;
          }
      }
  }

  void RigidVoronoiModel::compute_forces(double dt)
  {
    std::copy(fx_ext.begin(), fx_ext.end(), fx.begin());
    std::copy(fy_ext.begin(), fy_ext.end(), fy.begin());
    std::copy(mz_ext.begin(), mz_ext.end(), mz.begin());
    add_pressure_forces();
    detect_new_contacts(dt);
    const GrainKinematics g{x.data(),  y.data(),  radius.data(),
                            vx.data(), vy.data(), omega.data()};
    contacts.update_contacts(g, dt);
    // Gather per grain in contact order: thread-count independent sums.
    const int n = n_grains();
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
    for (int i = 0; i < n; ++i)
      for (int k = grain_contact_offset[i]; k < grain_contact_offset[i + 1]; ++k)
        {
          const int c = grain_contact[k] >> 1;
          if (grain_contact[k] & 1) // grain B
            {
              fx[i] += contacts.contact_fx[c];
              fy[i] += contacts.contact_fy[c];
              mz[i] += contacts.contact_mb[c];
            }
          else
            {
              fx[i] -= contacts.contact_fx[c];
              fy[i] -= contacts.contact_fy[c];
              mz[i] += contacts.contact_ma[c];
            }
        }
    add_platen_forces(dt);
  }

  void RigidVoronoiModel::step(double dt)
  {
    compute_forces(dt);
    const int    n     = n_grains();
    const double alpha = damping;
    auto         sign  = [](double v) { return (v > 0) - (v < 0); };
#pragma omp parallel for schedule(static) if (n >= parallel_threshold)
    for (int i = 0; i < n; ++i)
      {
        if (held[i])
          {
            vx[i] = vy[i] = omega[i] = 0;
            continue;
          }
        // Local non-viscous damping per degree of freedom (seed 004 §2.2,
        // as dem/engine/model.cc): -alpha |F| sign(v).
        const double Fx = fx[i] - alpha * std::abs(fx[i]) * sign(vx[i]);
        const double Fy = fy[i] - alpha * std::abs(fy[i]) * sign(vy[i]);
        const double M  = mz[i] - alpha * std::abs(mz[i]) * sign(omega[i]);
        vx[i] += dt * Fx / mass[i];
        vy[i] += dt * Fy / mass[i];
        omega[i] += dt * M / inertia[i];
        x[i] += dt * vx[i];
        y[i] += dt * vy[i];
        theta[i] += dt * omega[i];
      }
    for (auto &p : platens)
      {
        p.ux += dt * p.vx;
        p.uy += dt * p.vy;
      }
    time += dt;
  }

  double RigidVoronoiModel::stable_time_step(double safety) const
  {
    const int           n = n_grains();
    std::vector<double> Kt(n, 0.0), Kr(n, 0.0);
    // A point bears on a grain only on its cell outline, so its arm is at
    // most the cell's reach (farthest vertex from the disk centre). The
    // points of a contact whose grains have separated sit about the
    // midpoint of the two centres, far outside both cells; they carry no
    // force until the faces meet again, and then within the reach. Capping
    // the arm keeps such a contact from lowering the estimate with the
    // distance the grains have moved apart.
    std::vector<double> reach2(n, 0.0);
    for (int g = 0; g < n; ++g)
      for (int v = cell_offset[g]; v < cell_offset[g + 1]; ++v)
        reach2[g] =
            std::max(reach2[g], cell_rx[v] * cell_rx[v] + cell_ry[v] * cell_ry[v]);
    for (int c = 0; c < contacts.n_contacts(); ++c)
      {
        const auto  &k    = contacts.coefficients(c);
        const double kmax = std::max(k.kn, k.ks);
        const int    a = contacts.grain_a[c], b = contacts.grain_b[c];
        double       xr, yr, nx, ny;
        contacts.reference_frame(
            c,
            GrainKinematics{x.data(), y.data(), radius.data(), nullptr, nullptr, nullptr},
            xr, yr, nx, ny);
        for (int p = contacts.point_offset[c]; p < contacts.point_offset[c + 1]; ++p)
          {
            const double kp = kmax * contacts.area[p];
            const double px = xr - contacts.s[p] * ny, py = yr + contacts.s[p] * nx;
            for (int g : {a, b})
              {
                Kt[g] += kp;
                const double arm2 = (px - x[g]) * (px - x[g]) + (py - y[g]) * (py - y[g]);
                Kr[g] += kp * std::min(arm2, reach2[g]);
              }
          }
      }
    for (std::size_t i = 0; i < pp_grain.size(); ++i)
      {
        const double kp = std::max(pp_kn[i], pp_ks[i]) * pp_area[i];
        Kt[pp_grain[i]] += kp;
        Kr[pp_grain[i]] += kp * (pp_h[i] * pp_h[i] + pp_s[i] * pp_s[i]);
      }
    double lambda = 0;
    for (int i = 0; i < n; ++i)
      if (!held[i])
        lambda = std::max(lambda, 2 * (Kt[i] / mass[i] + Kr[i] / inertia[i]));
    if (!(lambda > 0))
      throw InputError("RigidVoronoiModel: no contact stiffness, no time step");
    return safety * 2 / std::sqrt(lambda);
  }

  double RigidVoronoiModel::kinetic_energy() const
  {
    double e = 0;
    for (int i = 0; i < n_grains(); ++i)
      e += 0.5 *
           (mass[i] * (vx[i] * vx[i] + vy[i] * vy[i]) + inertia[i] * omega[i] * omega[i]);
    return e;
  }

  double RigidVoronoiModel::side_displacement(Side side, int component) const
  {
    double sum = 0, weight = 0;
    for (const auto &e : boundary_edges)
      if (e.side == side)
        {
          const int g = e.grain;
          sum += e.length * (component == 0 ? x[g] - x0[g] : y[g] - y0[g]);
          weight += e.length;
        }
    return weight > 0 ? sum / weight : 0.0;
  }

  double RigidVoronoiModel::side_position(Side side, int component) const
  {
    double sum = 0, weight = 0;
    for (const auto &e : boundary_edges)
      if (e.side == side)
        {
          sum += e.length * (component == 0 ? x0[e.grain] : y0[e.grain]);
          weight += e.length;
        }
    return weight > 0 ? sum / weight : 0.0;
  }
} // namespace demfem::dem::voronoi
