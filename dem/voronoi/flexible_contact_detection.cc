// New contacts of the flexible Voronoi model under large displacements
// (seed 004 §2; dem/voronoi/flexible_model.h; docs/voronoi.md, "New
// contacts").
//
// The search for overlapping pairs is dem/voronoi/new_contact_search.h
// (shared with the rigid model): serial, in ascending (a, b) order, so the
// contacts, their point order and the gather lists do not depend on the
// thread count. This file forms the contacts of the pairs it finds.
#include "dem/voronoi/flexible_model.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem::voronoi
{
  void FlexibleVoronoiModel::update_disk_centres()
  {
    const int ng = n_grains();
    disk_cx.resize(ng); // sized once
    disk_cy.resize(ng);
    disk_active.resize(ng);
    for (int c = 0; c < ng; ++c)
      {
        // Grains of empty cells have no nodes and no disk in the model.
        disk_active[c] =
            mesh.grain_triangle_offset[c + 1] > mesh.grain_triangle_offset[c];
        disk_cx[c] = disk_active[c] ? disk_x(c) : 0.0;
        disk_cy[c] = disk_active[c] ? disk_y(c) : 0.0;
      }
  }

  void FlexibleVoronoiModel::rebuild_verlet_list()
  {
    ++n_verlet_rebuilds;
    search.rebuild(disk_cx.data(), disk_cy.data(), disk_radius.data(), disk_active.data(),
                   verlet_skin_fraction);
  }

  int FlexibleVoronoiModel::detect_new_contacts(double dt)
  {
    // Rebuild when some disk has moved more than half the skin.
    update_disk_centres();
    if (search.stale(disk_cx.data(), disk_cy.data(), disk_active.data()))
      rebuild_verlet_list();
    const int formed = form_new_contacts(false, dt);
    if (formed > 0)
      build_gather_lists();
    return formed;
  }

  int FlexibleVoronoiModel::form_new_contacts(bool at_install, double dt)
  {
    const auto &pairs =
        search.new_overlaps(disk_cx.data(), disk_cy.data(), disk_radius.data());
    for (const auto &[a, b] : pairs)
      form_contact(a, b, at_install, dt);
    return static_cast<int>(pairs.size());
  }

  void FlexibleVoronoiModel::form_contact(int a, int b, bool at_install, double dt)
  {
    const double xa = disk_x(a), ya = disk_y(a), xb = disk_x(b), yb = disk_y(b);
    const double ra = disk_radius[a], rb = disk_radius[b];
    const double dist = std::hypot(xb - xa, yb - ya);
    const double nx = (xb - xa) / dist, ny = (yb - ya) / dist, tx = -ny, ty = nx;
    const double U = ra + rb - dist; // > 0: the disks overlap
    // Reference point: the PCM contact point x_A + (R_A - U/2) n (delta = 0;
    // seed 004's reference point with no cell edge shared at install).
    const double xr = xa + (ra - U / 2) * nx, yr = ya + (ra - U / 2) * ny;
    // Seed 004 §2: in each grain the Voronoi edge closest to the contact
    // location; the cell's edges are the boundary segments (node 1, node 2)
    // of its fan triangles in the current mesh (merged short edges included).
    auto nearest_edge_length = [&](int g) {
      double best = HUGE_VAL, length = 0;
      for (int t = mesh.grain_triangle_offset[g]; t < mesh.grain_triangle_offset[g + 1];
           ++t)
        {
          const int p     = mesh.triangle_nodes[3 * t + 1],
                    q     = mesh.triangle_nodes[3 * t + 2];
          const double d2 = segment_distance2(xr, yr, x[p], y[p], x[q], y[q]);
          if (d2 < best)
            {
              best   = d2;
              length = std::hypot(x[q] - x[p], y[q] - y[p]);
            }
        }
      return length;
    };
    // Contact length: the shorter of the two selected edges (docs/voronoi.md,
    // "New contacts"). The two faces can be in contact over no more than the
    // shorter one; on the line of centres the contact (the DEM criterion)
    // need not lie where two cells that were never neighbours face each
    // other, so the projected overlap of the edges could be empty or
    // degenerate while the disks overlap, whereas the shorter edge is always
    // a positive length of the grains' own scale. Centred on the reference
    // point, the points' forces have no moment about it at formation (the
    // PCM force), and for two cells pressed face to face it is the length
    // of the face they share.
    const double L = std::min(nearest_edge_length(a), nearest_edge_length(b));
    const int    k = contacts.add_contact(a, b, xa, ya, ra, xb, yb, rb, xr - 0.5 * L * tx,
                                          yr - 0.5 * L * ty, xr + 0.5 * L * tx,
                                          yr + 0.5 * L * ty, scheme);
    contacts.offset[k] = 0; // the PCM plane itself, not roundoff of it
    for (int p = contacts.point_offset[k]; p < contacts.point_offset[k + 1]; ++p)
      {
        // Unbonded: a contact between separate grains carries friction
        // only. Its normal displacement is measured from the touching
        // disks (u_n = -U now), so the force is kn A_i times the overlap,
        // the DEM law the seed keeps; at install it starts stress free.
        const double X = xr + contacts.s[p] * tx, Y = yr + contacts.s[p] * ty;
        const int    ta = mesh.locate(a, x.data(), y.data(), X, Y);
        const int    tb = mesh.locate(b, x.data(), y.data(), X, Y);
        triangle_a.push_back(ta);
        triangle_b.push_back(tb);
        contacts.crack[p] = PointCrack::unbonded;
        // The positions already hold the last velocity increment (central
        // differences: x^n = x^(n-1) + dt v^(n-1/2)), and update_contact_
        // points adds dt v^(n-1/2) . n once more in this step: subtract it
        // here, with the same arithmetic, so that u_n = -U after the update.
        double Na[3], Nb[3], vrx = 0, vry = 0;
        mesh.shape_functions(ta, x.data(), y.data(), X, Y, Na);
        mesh.shape_functions(tb, x.data(), y.data(), X, Y, Nb);
        for (int i = 0; i < 3; ++i)
          {
            const int ma = mesh.triangle_nodes[3 * ta + i],
                      mb = mesh.triangle_nodes[3 * tb + i];
            vrx += Nb[i] * vx[mb] - Na[i] * vx[ma];
            vry += Nb[i] * vy[mb] - Na[i] * vy[ma];
          }
        contacts.un[p] = at_install ? 0.0 : -U - (vrx * nx + vry * ny) * dt;
      }
    const int np = contacts.n_points();
    point_fx.resize(np, 0.0);
    point_fy.resize(np, 0.0);
    point_N.resize(6 * np, 0.0);
  }
} // namespace demfem::dem::voronoi
