// New contacts of the rigid Voronoi model (seed 004 §2;
// dem/voronoi/rigid_model.h; docs/voronoi.md, "New contacts"), formed as in
// the flexible model (dem/voronoi/flexible_contact_detection.cc) from the
// pairs of the shared search (dem/voronoi/new_contact_search.h): serial, in
// ascending (a, b) order, so the contacts and the per-grain gather lists do
// not depend on the thread count.
#include "dem/voronoi/rigid_model.h"

#include <cmath>

namespace demfem::dem::voronoi
{
  void RigidVoronoiModel::rebuild_verlet_list()
  {
    ++n_verlet_rebuilds;
    search.rebuild(x.data(), y.data(), radius.data(), has_cell.data(),
                   verlet_skin_fraction);
  }

  int RigidVoronoiModel::detect_new_contacts(double dt)
  {
    // Rebuild when some disk has moved more than half the skin.
    if (search.stale(x.data(), y.data(), has_cell.data()))
      rebuild_verlet_list();
    const int formed = form_new_contacts(false, dt);
    if (formed > 0)
      build_grain_contact_lists();
    return formed;
  }

  int RigidVoronoiModel::form_new_contacts(bool at_install, double dt)
  {
    const auto &pairs = search.new_overlaps(x.data(), y.data(), radius.data());
    for (const auto &[a, b] : pairs)
      form_contact(a, b, at_install, dt);
    return static_cast<int>(pairs.size());
  }

  void RigidVoronoiModel::form_contact(int a, int b, bool at_install, double dt)
  {
    const double xa = x[a], ya = y[a], xb = x[b], yb = y[b];
    const double ra = radius[a], rb = radius[b];
    const double dist = std::hypot(xb - xa, yb - ya);
    const double nx = (xb - xa) / dist, ny = (yb - ya) / dist, tx = -ny, ty = nx;
    const double U = ra + rb - dist; // > 0: the disks overlap
    // Reference point: the PCM contact point x_A + (R_A - U/2) n (delta = 0;
    // seed 004's reference point with no cell edge shared at install).
    const double xr = xa + (ra - U / 2) * nx, yr = ya + (ra - U / 2) * ny;
    // Seed 004 §2: in each grain the Voronoi edge closest to the contact
    // location, in the current configuration (the install cell polygon
    // turned by theta and carried by the centre; a rigid edge keeps its
    // length).
    auto nearest_edge_length = [&](int g) {
      const double c = std::cos(theta[g]), s = std::sin(theta[g]);
      const int    v0 = cell_offset[g], nv = cell_offset[g + 1] - v0;
      double       best = HUGE_VAL, length = 0;
      for (int k = 0; k < nv; ++k)
        {
          const int    p = v0 + k, q = v0 + (k + 1) % nv;
          const double px = x[g] + c * cell_rx[p] - s * cell_ry[p];
          const double py = y[g] + s * cell_rx[p] + c * cell_ry[p];
          const double qx = x[g] + c * cell_rx[q] - s * cell_ry[q];
          const double qy = y[g] + s * cell_rx[q] + c * cell_ry[q];
          const double d2 = segment_distance2(xr, yr, px, py, qx, qy);
          if (d2 < best)
            {
              best   = d2;
              length = std::hypot(cell_rx[q] - cell_rx[p], cell_ry[q] - cell_ry[p]);
            }
        }
      return length;
    };
    // Contact length: the shorter of the two selected edges, centred on the
    // reference point (docs/voronoi.md, "New contacts", the flexible model's
    // rule): the faces can touch over no more than the shorter one, and the
    // points' forces have no moment about the reference point at formation.
    const double L = std::min(nearest_edge_length(a), nearest_edge_length(b));
    const int    k = contacts.add_contact(a, b, xa, ya, ra, xb, yb, rb, xr - 0.5 * L * tx,
                                          yr - 0.5 * L * ty, xr + 0.5 * L * tx,
                                          yr + 0.5 * L * ty, scheme);
    contacts.offset[k] = 0; // the PCM plane itself, not roundoff of it
    // The reference frame exactly as RigidVoronoiContacts::update_contacts
    // evaluates it, so the increment subtracted below is the one it adds.
    const GrainKinematics g{x.data(),  y.data(),  radius.data(),
                            vx.data(), vy.data(), omega.data()};
    double                xr_k, yr_k, nx_k, ny_k;
    contacts.reference_frame(k, g, xr_k, yr_k, nx_k, ny_k);
    const double tx_k = -ny_k, ty_k = nx_k;
    for (int p = contacts.point_offset[k]; p < contacts.point_offset[k + 1]; ++p)
      {
        // Unbonded: a contact between separate grains carries friction
        // only. Its normal displacement is measured from the touching
        // disks (u_n = -U now), so the force is kn A_i times the overlap,
        // the DEM law the seed keeps; at install it starts stress free.
        contacts.crack[p] = PointCrack::unbonded;
        // The positions already hold the last velocity increment (central
        // differences: x^n = x^(n-1) + dt v^(n-1/2)), and update_contacts
        // adds dt v^(n-1/2) . n once more in this step: subtract it here,
        // with the same arithmetic, so that u_n = -U after the update.
        const double px = xr_k + contacts.s[p] * tx_k, py = yr_k + contacts.s[p] * ty_k;
        const double rax = px - x[a], ray = py - y[a];
        const double rbx = px - x[b], rby = py - y[b];
        const double vrx = (vx[b] - omega[b] * rby) - (vx[a] - omega[a] * ray);
        const double vry = (vy[b] + omega[b] * rbx) - (vy[a] + omega[a] * rax);
        contacts.un[p]   = at_install ? 0.0 : -U - (vrx * nx_k + vry * ny_k) * dt;
      }
  }
} // namespace demfem::dem::voronoi
