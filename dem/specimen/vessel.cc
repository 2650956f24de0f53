// Material vessels (fistPkg §4.1, Table 6).
#include "dem/specimen/vessel.h"

#include <algorithm>
#include <cmath>

namespace demfem::dem
{
  void VesselParams::validate(const std::string &where, int dim) const
  {
    const double inf = HUGE_VAL;
    if (shape != "box" && shape != "cylinder")
      throw InputError(where + ": parameter 'shape' = '" + shape +
                       "' is not one of box, cylinder");
    if (shape == "cylinder" && dim != 3)
      throw InputError(where + ": parameter 'shape' = 'cylinder' needs dimension 3 "
                               "(the 2D vessel is a box, fistPkg Table 6)");
    check_range(where, "H", H, 0, inf, true);
    check_range(where, "W", W, 0, inf, true);
    if (dim == 3 && shape == "box")
      check_range(where, "D", D, 0, inf, true);
    check_range(where, "expand", expand, 1, inf);
    check_range(where, "inset_l", inset_l, 0, 1, true);
    check_range(where, "inset_d", inset_d, 0, 1, true);
    check_range(where, "emod", emod, 0, inf);
    if (shape == "cylinder")
      check_range(where, "segments", segments, 8, 100000);
  }

  template <int dim>
  double Region<dim>::volume() const
  {
    return dim == 2 ? M_PI * radius * radius
                    : 4.0 / 3.0 * M_PI * radius * radius * radius;
  }

  namespace
  {
    template <int dim>
    double coord(const Walls<dim> &w, int v, int a)
    {
      return w.vertex[v][a];
    }

    // "x-", "x+", ... : the wall bounding axis a below (s = 0) or above.
    std::string wall_name(int a, int s)
    {
      static const char *axis_name[3] = {"x", "y", "z"};
      return std::string(axis_name[a]) + (s ? "+" : "-");
    }
  } // namespace

  template <int dim>
  double Vessel<dim>::radius(const Walls<dim> &w) const
  {
    if (!cylinder())
      return 0;
    // Vertices sit at R / cos(pi / n) so that the flats are at distance R.
    const Vec<dim> &x = w.vertex[side_vertices[0]];
    const double    r = std::hypot(x[0] - center[0], x[1] - center[1]);
    return r * std::cos(M_PI / params.segments);
  }

  template <int dim>
  std::vector<double> Vessel<dim>::tributary_areas(const Walls<dim>       &w,
                                                   const std::vector<int> &chain) const
  {
    // Hat function of vertex k: 1 at y_k, 0 at its neighbours; on the facet
    // [y_k, y_k+1] the weight of y_k is (y_k+1 - y) / (y_k+1 - y_k), and
    // its integral over [lo, hi] is (u(lo) - u(hi)) with
    // u(y) = (y_k+1 - y)^2 / (2 (y_k+1 - y_k)), both limits clipped.
    const int    ax  = dim - 1;
    const double ylo = coord(w, lo_vertex[ax], ax), yhi = coord(w, hi_vertex[ax], ax);
    std::vector<double> A(chain.size(), 0.0);
    for (std::size_t k = 0; k + 1 < chain.size(); ++k)
      {
        const double y0 = coord(w, chain[k], ax), y1 = coord(w, chain[k + 1], ax);
        const double a = std::clamp(ylo, y0, y1), b = std::clamp(yhi, y0, y1);
        if (b <= a)
          continue;
        const double L = y1 - y0;
        A[k] += ((y1 - a) * (y1 - a) - (y1 - b) * (y1 - b)) / (2 * L);
        A[k + 1] += ((a - y0) * (a - y0) - (b - y0) * (b - y0)) / (-2 * L);
      }
    return A;
  }

  namespace
  {
    // Tributary-area weighted mean coordinate a of a flexible wall.
    template <int dim>
    double mean_position(const Vessel<dim> &v, const Walls<dim> &w,
                         const std::vector<int> &chain, int a)
    {
      const auto A   = v.tributary_areas(w, chain);
      double     sum = 0, x = 0;
      for (std::size_t k = 0; k < chain.size(); ++k)
        {
          sum += A[k];
          x += A[k] * w.vertex[chain[k]][a];
        }
      return sum > 0 ? x / sum : w.vertex[chain[chain.size() / 2]][a];
    }
  } // namespace

  template <int dim>
  void Vessel<dim>::make_flexible(Walls<dim> &w, int a, int segments, double park)
  {
    if (dim != 2 || cylinder() || a == dim - 1 || flexible(a))
      throw InputError("vessel: flexible lateral walls are made once, for the lateral "
                       "axis of a 2D box");
    if (segments < 1)
      throw InputError("vessel: parameter 'segments' = " + std::to_string(segments) +
                       " is not >= 1");
    const int    ax  = dim - 1;
    const double ylo = coord(w, lo_vertex[ax], ax), yhi = coord(w, hi_vertex[ax], ax);
    const double margin = 0.5 * (params.expand - 1) * (yhi - ylo);
    std::vector<double> y{ylo - margin};
    for (int k = 0; k <= segments; ++k)
      y.push_back(ylo + (yhi - ylo) * k / segments);
    if (margin > 0)
      y.push_back(yhi + margin);
    else
      y.erase(y.begin());
    const double xlo = coord(w, lo_vertex[a], a), xhi = coord(w, hi_vertex[a], a);
    translate_outward(w, a, park);
    for (int s = 0; s < 2; ++s)
      {
        const int        id = w.add_wall(wall_name(a, s) + " flexible");
        std::vector<int> chain;
        for (double yk : y)
          {
            Vec<dim> x = Vec<dim>::Zero();
            x[a]       = s ? xhi : xlo;
            x[ax]      = yk;
            chain.push_back(w.add_vertex(x));
          }
        for (std::size_t k = 0; k + 1 < chain.size(); ++k)
          {
            std::array<int, dim> f{};
            f[0] = chain[k];
            f[1] = chain[k + 1];
            w.add_facet(id, f);
          }
        (s ? hi : lo)[a]               = id;
        (s ? hi_vertex : lo_vertex)[a] = chain[margin > 0 ? 1 : 0];
        (s ? hi_chain : lo_chain)[a]   = chain;
      }
  }

  template <int dim>
  double Vessel<dim>::length(const Walls<dim> &w, int a) const
  {
    if (flexible(a))
      return mean_position(*this, w, hi_chain[a], a) -
             mean_position(*this, w, lo_chain[a], a);
    if (lo[a] >= 0)
      return coord(w, hi_vertex[a], a) - coord(w, lo_vertex[a], a);
    return 2 * radius(w);
  }

  template <int dim>
  double Vessel<dim>::area(const Walls<dim> &w, int a) const
  {
    if (cylinder())
      {
        const int    n = params.segments;
        const double R = radius(w);
        if (a == dim - 1)
          return n * R * R * std::tan(M_PI / n);                    // polygon area
        return 2 * n * R * std::tan(M_PI / n) * length(w, dim - 1); // lateral surface
      }
    double A = 1;
    for (int b = 0; b < dim; ++b)
      if (b != a)
        A *= length(w, b);
    return A;
  }

  template <int dim>
  double Vessel<dim>::volume(const Walls<dim> &w) const
  {
    if (cylinder())
      return area(w, dim - 1) * length(w, dim - 1);
    double V = 1;
    for (int a = 0; a < dim; ++a)
      V *= length(w, a);
    return V;
  }

  template <int dim>
  double Vessel<dim>::wall_stress(const Walls<dim> &w, int a) const
  {
    if (lo[a] >= 0)
      {
        // Grains push the lo wall towards -a and the hi wall towards +a.
        const double P =
            0.5 * (w.wall_force(hi[a])[a] - w.wall_force(lo[a])[a]) / area(w, a);
        return -P;
      }
    double Fr = 0;
    for (int v : side_vertices)
      {
        Vec<dim> r = w.vertex[v] - center;
        r[dim - 1] = 0;
        Fr += w.vertex_force[v].dot(r.normalized());
      }
    return -Fr / area(w, a);
  }

  template <int dim>
  double Vessel<dim>::wall_strain(const Walls<dim> &w, int a) const
  {
    return (length(w, a) - initial_length[a]) / initial_length[a];
  }

  template <int dim>
  void Vessel<dim>::reset_strain_reference(const Walls<dim> &w)
  {
    for (int a = 0; a < dim; ++a)
      initial_length[a] = length(w, a);
  }

  template <int dim>
  void Vessel<dim>::set_velocity(Walls<dim> &w, int a, double v) const
  {
    if (lo[a] >= 0)
      {
        Vec<dim> e = Vec<dim>::Zero();
        e[a]       = v;
        w.set_wall_velocity(lo[a], -e);
        w.set_wall_velocity(hi[a], e);
        return;
      }
    for (int k : side_vertices)
      {
        Vec<dim> r           = w.vertex[k] - center;
        r[dim - 1]           = 0;
        w.vertex_velocity[k] = v * r.normalized();
      }
  }

  template <int dim>
  void Vessel<dim>::translate_outward(Walls<dim> &w, int a, double delta) const
  {
    if (lo[a] >= 0)
      {
        std::vector<char> moved(w.vertex.size(), 0);
        for (std::size_t f = 0; f < w.n_facets(); ++f)
          for (int v : w.facet[f])
            if (!moved[v] && (w.facet_wall[f] == lo[a] || w.facet_wall[f] == hi[a]))
              {
                w.vertex[v][a] += w.facet_wall[f] == lo[a] ? -delta : delta;
                moved[v] = 1;
              }
        return;
      }
    const double scale = (radius(w) + delta) / radius(w);
    for (int k : side_vertices)
      for (int b = 0; b < dim - 1; ++b)
        w.vertex[k][b] = center[b] + scale * (w.vertex[k][b] - center[b]);
  }

  template <int dim>
  bool Vessel<dim>::contains(const Walls<dim> &w, const Vec<dim> &x, double margin) const
  {
    for (int a = 0; a < dim; ++a)
      if (lo[a] >= 0 && (x[a] < coord(w, lo_vertex[a], a) + margin ||
                         x[a] > coord(w, hi_vertex[a], a) - margin))
        return false;
    if (cylinder())
      return std::hypot(x[0] - center[0], x[1] - center[1]) <= radius(w) - margin;
    return true;
  }

  template <int dim>
  Vessel<dim> make_vessel(Walls<dim> &w, const VesselParams &p, const std::string &where)
  {
    p.validate(where, dim);
    Vessel<dim> v;
    v.params = p;
    v.lo.fill(-1);
    v.hi.fill(-1);
    v.lo_vertex.fill(-1);
    v.hi_vertex.fill(-1);
    const double e = p.expand;
    // Half lengths: x = W, (3D) y = D, axial = H.
    std::array<double, dim> h;
    h[0]       = p.W / 2;
    h[dim - 1] = p.H / 2;
    if (dim == 3)
      h[1] = p.shape == "cylinder" ? p.W / 2 : p.D / 2;
    auto planar = [&](int a) {
      for (int s = 0; s < 2; ++s)
        {
          const int id         = w.add_wall(wall_name(a, s));
          (s ? v.hi : v.lo)[a] = id;
          const double pos     = s ? h[a] : -h[a];
          if constexpr (dim == 2)
            {
              const int b = 1 - a;
              Vec<2>    x1, x2;
              x1[a] = x2[a] = pos;
              x1[b]         = -e * h[b];
              x2[b]         = e * h[b];
              const int v1 = w.add_vertex(x1), v2 = w.add_vertex(x2);
              w.add_facet(id, {v1, v2});
              (s ? v.hi_vertex : v.lo_vertex)[a] = v1;
            }
          else if (p.shape == "box")
            {
              const int b = (a + 1) % 3, c = (a + 2) % 3;
              int       q[4];
              for (int k = 0; k < 4; ++k)
                {
                  Vec<3> x;
                  x[a] = pos;
                  x[b] = (k == 0 || k == 3 ? -1 : 1) * e * h[b];
                  x[c] = (k < 2 ? -1 : 1) * e * h[c];
                  q[k] = w.add_vertex(x);
                }
              w.add_facet(id, {q[0], q[1], q[2]});
              w.add_facet(id, {q[0], q[2], q[3]});
              (s ? v.hi_vertex : v.lo_vertex)[a] = q[0];
            }
          else // cylinder end plates: fans of triangles over a disk of e R
            {
              const int n         = p.segments;
              Vec<3>    c0        = Vec<3>::Zero();
              c0[2]               = pos;
              const int        ic = w.add_vertex(c0);
              std::vector<int> ring(n);
              const double     Rp = e * h[0] / std::cos(M_PI / n);
              for (int k = 0; k < n; ++k)
                {
                  const double t = 2 * M_PI * k / n;
                  ring[k] = w.add_vertex(Vec<3>(Rp * std::cos(t), Rp * std::sin(t), pos));
                }
              for (int k = 0; k < n; ++k)
                w.add_facet(id, {ic, ring[k], ring[(k + 1) % n]});
              (s ? v.hi_vertex : v.lo_vertex)[a] = ic;
            }
        }
    };
    if (p.shape == "box")
      for (int a = 0; a < dim; ++a)
        planar(a);
    else
      {
        planar(dim - 1);
        if constexpr (dim == 3)
          {
            const int id        = w.add_wall("side");
            v.side              = id;
            const int        n  = p.segments;
            const double     Rv = h[0] / std::cos(M_PI / n);
            std::vector<int> lo_ring(n), hi_ring(n);
            for (int k = 0; k < n; ++k)
              {
                const double t = 2 * M_PI * (k + 0.5) / n;
                lo_ring[k] =
                    w.add_vertex(Vec<3>(Rv * std::cos(t), Rv * std::sin(t), -e * h[2]));
                hi_ring[k] =
                    w.add_vertex(Vec<3>(Rv * std::cos(t), Rv * std::sin(t), e * h[2]));
                v.side_vertices.push_back(lo_ring[k]);
                v.side_vertices.push_back(hi_ring[k]);
              }
            for (int k = 0; k < n; ++k)
              {
                const int k1 = (k + 1) % n;
                w.add_facet(id, {lo_ring[k], lo_ring[k1], hi_ring[k1]});
                w.add_facet(id, {lo_ring[k], hi_ring[k1], hi_ring[k]});
              }
          }
      }
    v.reset_strain_reference(w);
    // Measurement regions (§4.1): three along the axis of the largest
    // dimension, spanning inset_l * L_max, diameter inset_d * L_min.
    int    amax = 0;
    double Lmax = 0, Lmin = HUGE_VAL;
    for (int a = 0; a < dim; ++a)
      {
        const double L = v.length(w, a);
        if (L > Lmax)
          {
            Lmax = L;
            amax = a;
          }
        Lmin = std::min(Lmin, L);
      }
    const double r    = 0.5 * p.inset_d * Lmin;
    const double half = std::max(0.0, 0.5 * p.inset_l * Lmax - r);
    for (int k = 0; k < 3; ++k)
      {
        v.regions[k].radius       = r;
        v.regions[k].center       = Vec<dim>::Zero();
        v.regions[k].center[amax] = (k - 1) * half;
      }
    return v;
  }

  template struct Region<2>;
  template struct Region<3>;
  template struct Vessel<2>;
  template struct Vessel<3>;
  template Vessel<2> make_vessel(Walls<2> &, const VesselParams &, const std::string &);
  template Vessel<3> make_vessel(Walls<3> &, const VesselParams &, const std::string &);
} // namespace demfem::dem
