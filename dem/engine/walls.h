#pragma once
// Walls made of facets: segments (2D) or triangles (3D) over shared
// vertices. Each vertex has its own velocity so a wall can translate as a
// platen or deform with a continuum boundary (wall-facet coupling).
#include "dem/engine/types.h"

#include <array>
#include <string>
#include <vector>

namespace demfem::dem
{
  template <int dim>
  struct Walls
  {
    std::vector<Vec<dim>>                   vertex;          ///< positions
    std::vector<Vec<dim>>                   vertex_velocity; ///< prescribed
    std::vector<Vec<dim>>                   vertex_force;    ///< contact force of the step
    std::vector<std::array<int, dim>>       facet;           ///< vertex indices
    std::vector<int>                        facet_wall;      ///< owning wall id
    std::vector<std::string>                wall_name;

    std::size_t n_facets() const { return facet.size(); }

    /// Adds an empty wall and returns its id.
    int add_wall(const std::string &name);
    /// Adds a vertex; returns its index.
    int add_vertex(const Vec<dim> &x);
    /// Adds a facet of wall `wall` over existing vertices. The facet's
    /// normal side does not matter: contacts use the closest point.
    void add_facet(int wall, const std::array<int, dim> &vertices);

    /// Sets the velocity of every vertex of wall `wall`.
    void set_wall_velocity(int wall, const Vec<dim> &v);
    /// Sum of the contact forces on the vertices of wall `wall` (force that
    /// the particles exert on the wall).
    Vec<dim> wall_force(int wall) const;

    /// Closest point of facet k to p, and its barycentric weights.
    Vec<dim> closest_point(std::size_t k, const Vec<dim> &p, std::array<double, dim> &weights) const;

    /// Moves the vertices by their velocity over dt.
    void move(double dt);
  };
} // namespace demfem::dem
