#include "dem/engine/walls.h"

#include <algorithm>

namespace demfem::dem
{
  template <int dim>
  int Walls<dim>::add_wall(const std::string &name)
  {
    wall_name.push_back(name);
    return static_cast<int>(wall_name.size()) - 1;
  }

  template <int dim>
  int Walls<dim>::add_vertex(const Vec<dim> &x)
  {
    vertex.push_back(x);
    vertex_velocity.push_back(Vec<dim>::Zero());
    vertex_force.push_back(Vec<dim>::Zero());
    return static_cast<int>(vertex.size()) - 1;
  }

  template <int dim>
  void Walls<dim>::add_facet(int wall, const std::array<int, dim> &vertices)
  {
    if (wall < 0 || wall >= static_cast<int>(wall_name.size()))
      throw InputError("Walls::add_facet: wall id " + std::to_string(wall) + " does not exist");
    for (int v : vertices)
      if (v < 0 || v >= static_cast<int>(vertex.size()))
        throw InputError("Walls::add_facet: vertex index " + std::to_string(v) + " out of range");
    facet.push_back(vertices);
    facet_wall.push_back(wall);
  }

  template <int dim>
  void Walls<dim>::set_wall_velocity(int wall, const Vec<dim> &v)
  {
    for (std::size_t k = 0; k < facet.size(); ++k)
      if (facet_wall[k] == wall)
        for (int i : facet[k])
          vertex_velocity[i] = v;
  }

  template <int dim>
  Vec<dim> Walls<dim>::wall_force(int wall) const
  {
    // A vertex shared by several facets of the wall is counted once.
    std::vector<char> seen(vertex.size(), 0);
    Vec<dim>          sum = Vec<dim>::Zero();
    for (std::size_t k = 0; k < facet.size(); ++k)
      if (facet_wall[k] == wall)
        for (int i : facet[k])
          if (!seen[i])
            {
              seen[i] = 1;
              sum += vertex_force[i];
            }
    return sum;
  }

  template <>
  Vec<2> Walls<2>::closest_point(std::size_t k, const Vec<2> &p, std::array<double, 2> &wgt) const
  {
    const Vec<2> &a = vertex[facet[k][0]], &b = vertex[facet[k][1]];
    const Vec<2>  ab = b - a;
    const double  l2 = ab.squaredNorm();
    double        u  = l2 > 0 ? (p - a).dot(ab) / l2 : 0.0;
    u                = std::clamp(u, 0.0, 1.0);
    wgt              = {1 - u, u};
    return a + u * ab;
  }

  // Closest point on a triangle by Voronoi regions (vertex, edge, face).
  template <>
  Vec<3> Walls<3>::closest_point(std::size_t k, const Vec<3> &p, std::array<double, 3> &wgt) const
  {
    const Vec<3> &a = vertex[facet[k][0]], &b = vertex[facet[k][1]], &c = vertex[facet[k][2]];
    const Vec<3>  ab = b - a, ac = c - a, ap = p - a;
    const double  d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0)
      return wgt = {1, 0, 0}, a;
    const Vec<3> bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3)
      return wgt = {0, 1, 0}, b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
      {
        const double v = d1 / (d1 - d3);
        wgt            = {1 - v, v, 0};
        return a + v * ab;
      }
    const Vec<3> cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6)
      return wgt = {0, 0, 1}, c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
      {
        const double w = d2 / (d2 - d6);
        wgt            = {1 - w, 0, w};
        return a + w * ac;
      }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
      {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        wgt            = {0, 1 - w, w};
        return b + w * (c - b);
      }
    const double denom = 1 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    wgt = {1 - v - w, v, w};
    return a + ab * v + ac * w;
  }

  template <int dim>
  void Walls<dim>::move(double dt)
  {
    for (std::size_t i = 0; i < vertex.size(); ++i)
      vertex[i] += dt * vertex_velocity[i];
  }

  template struct Walls<2>;
  template struct Walls<3>;
} // namespace demfem::dem
