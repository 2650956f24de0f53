// Rigid Voronoi contact model (dem/voronoi/rigid_contact.h).
#include "dem/voronoi/rigid_contact.h"

#include <cmath>
#include <string>

namespace demfem::dem::voronoi
{
  RigidVoronoiContacts::RigidVoronoiContacts(const ContactMaterial &m)
      : material(m)
  {
    m.validate("Voronoi contact material");
    point_offset.push_back(0);
  }

  void RigidVoronoiContacts::add_from_tessellation(const Tessellation        &tess,
                                                   const std::vector<double> &x,
                                                   const std::vector<double> &y,
                                                   const std::vector<double> &radius,
                                                   PointScheme                scheme)
  {
    if ((int)x.size() != tess.n_cells() || y.size() != x.size() ||
        radius.size() != x.size())
      throw InputError("RigidVoronoiContacts: the packing has " +
                       std::to_string(x.size()) + " disks, the tessellation " +
                       std::to_string(tess.n_cells()) + " cells");
    for (int c = 0; c < tess.n_cells(); ++c)
      for (int e = tess.begin(c); e < tess.end(c); ++e)
        {
          const int d = tess.edge_neighbour[e];
          if (d <= c) // boundary (-1) or already added from cell d
            continue;
          const int f = tess.next(c, e);
          add_contact(c, d, x[c], y[c], radius[c], x[d], y[d], radius[d],
                      tess.vertex_x[e], tess.vertex_y[e], tess.vertex_x[f],
                      tess.vertex_y[f], scheme);
        }
  }

  int RigidVoronoiContacts::add_contact(int a, int b, double xa, double ya, double ra,
                                        double xb, double yb, double rb, double ex0,
                                        double ey0, double ex1, double ey1,
                                        PointScheme scheme)
  {
    const double dist = std::hypot(xb - xa, yb - ya);
    if (!(dist > 0))
      throw InputError("RigidVoronoiContacts: grains " + std::to_string(a) + " and " +
                       std::to_string(b) + " have the same centre");
    const double nx = (xb - xa) / dist, ny = (yb - ya) / dist;
    const double tx = -ny, ty = nx; // t = k x n
    const double U = ra + rb - dist;
    // PCM contact point x_A + (R_A - U/2) n; delta = (edge point - PCM point).n
    // (a Laguerre edge is perpendicular to n, so either end gives it).
    const double pcm = ra - U / 2;
    const double mx = 0.5 * (ex0 + ex1), my = 0.5 * (ey0 + ey1);
    const double delta = (mx - xa) * nx + (my - ya) * ny - pcm;
    const double xr = xa + (pcm + delta) * nx, yr = ya + (pcm + delta) * ny;
    const double L = std::hypot(ex1 - ex0, ey1 - ey0);
    const double A = L * material.thickness;

    // Seed 004 §2.5: kn per unit area; in the deformability mode kn = E_c / d
    // with d the centre distance at install (docs/voronoi.md).
    law.push_back(SofteningCoefficients::derive(material.for_length(dist)));
    const SofteningCoefficients &coeff = law.back();
    grain_a.push_back(a);
    grain_b.push_back(b);
    offset.push_back(delta);
    edge_length.push_back(L);
    auto add_point = [&](double si, double ai) {
      s.push_back(si);
      area.push_back(ai);
      un.push_back(0);
      wn.push_back(0);
      fs.push_back(0);
      damage_t.push_back(0);
      damage_s.push_back(0);
      crack.push_back(coeff.initial_crack());
      fn.push_back(0);
    };
    if (scheme == PointScheme::lobatto3)
      {
        // Seed 004 eq. 11: s_i = (x_i - x_r).t at the edge ends and middle.
        const double s0 = (ex0 - xr) * tx + (ey0 - yr) * ty;
        const double s1 = (ex1 - xr) * tx + (ey1 - yr) * ty;
        add_point(s0, A / 6);
        add_point(0.5 * (s0 + s1), 2 * A / 3);
        add_point(s1, A / 6);
      }
    else
      add_point(0.0, A);
    point_offset.push_back(static_cast<int>(s.size()));
    return n_contacts() - 1;
  }

  void RigidVoronoiContacts::reference_frame(int c, const GrainKinematics &g, double &xr,
                                             double &yr, double &nx, double &ny) const
  {
    const int    a = grain_a[c], b = grain_b[c];
    const double dx = g.x[b] - g.x[a], dy = g.y[b] - g.y[a];
    const double dist = std::hypot(dx, dy);
    nx                = dx / dist;
    ny                = dy / dist;
    const double U    = g.radius[a] + g.radius[b] - dist;
    const double ra   = g.radius[a] - U / 2 + offset[c];
    xr                = g.x[a] + ra * nx;
    yr                = g.y[a] + ra * ny;
  }

  void RigidVoronoiContacts::update_contacts(const GrainKinematics &g, double dt)
  {
    const int nc = n_contacts();
    contact_fx.resize(nc); // no allocation once sized
    contact_fy.resize(nc);
    contact_ma.resize(nc);
    contact_mb.resize(nc);
    // Each contact touches only its own points and its own slots: the
    // result does not depend on the thread count.
#pragma omp parallel for schedule(static) if (nc >= parallel_threshold)
    for (int c = 0; c < nc; ++c)
      {
        const int a = grain_a[c], b = grain_b[c];
        double    xr, yr, nx, ny;
        reference_frame(c, g, xr, yr, nx, ny);
        const double tx = -ny, ty = nx;
        double       Fx = 0, Fy = 0, Ma = 0, Mb = 0; // on B; moments about centres
        for (int p = point_offset[c]; p < point_offset[c + 1]; ++p)
          {
            const double px = xr + s[p] * tx, py = yr + s[p] * ty;
            // Arms from the centres; velocity of a grain at the point is
            // v + omega k x r = v + omega (-r_y, r_x).
            const double rax = px - g.x[a], ray = py - g.y[a];
            const double rbx = px - g.x[b], rby = py - g.y[b];
            const double vrx =
                (g.vx[b] - g.omega[b] * rby) - (g.vx[a] - g.omega[a] * ray);
            const double vry =
                (g.vy[b] + g.omega[b] * rbx) - (g.vy[a] + g.omega[a] * rax);
            const double d_un = (vrx * nx + vry * ny) * dt;
            const double d_us = (vrx * tx + vry * ty) * dt;
            const double f_n  = update_point(
                 law[c], area[p], d_un, d_us,
                 PointState{un[p], wn[p], fs[p], damage_t[p], damage_s[p], crack[p]});
            fn[p] = f_n;
            // Point force on B: -F_n n + F_s t.
            const double fx = -f_n * nx + fs[p] * tx;
            const double fy = -f_n * ny + fs[p] * ty;
            Fx += fx;
            Fy += fy;
            Mb += rbx * fy - rby * fx;
            Ma -= rax * fy - ray * fx;
          }
        contact_fx[c] = Fx;
        contact_fy[c] = Fy;
        contact_ma[c] = Ma;
        contact_mb[c] = Mb;
      }
  }

  void RigidVoronoiContacts::update(const GrainKinematics &g, double dt,
                                    const GrainForces &out)
  {
    update_contacts(g, dt);
    const int nc = n_contacts();
    for (int c = 0; c < nc; ++c)
      {
        const int a = grain_a[c], b = grain_b[c];
        out.fx[b] += contact_fx[c];
        out.fy[b] += contact_fy[c];
        out.mz[b] += contact_mb[c];
        out.fx[a] -= contact_fx[c];
        out.fy[a] -= contact_fy[c];
        out.mz[a] += contact_ma[c];
      }
  }
} // namespace demfem::dem::voronoi
