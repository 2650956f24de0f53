#pragma once
// The DEM model: particles, walls, contacts grouped by law, contact
// detection, central-difference integration with local damping, critical
// time step, crack records and energy/stability monitoring.
#include "common/growth_monitor.h"
#include "dem/engine/contact_group.h"
#include "dem/engine/neighbor_grid.h"

#include <array>
#include <functional>
#include <memory>
#include <unordered_map>

namespace demfem::dem
{
  /// One bond breakage (fistPkg §3.4; memo footnote 3).
  template <int dim>
  struct CrackRecord
  {
    std::int64_t id1 = 0, id2 = 0; ///< particle ids (id2 = -1 - facet for walls)
    int          element = 0;      ///< element of the interface (0-based)
    int          mode    = 0;      ///< 0 tension, 1 shear
    BondType     type    = BondType::flat_joint; ///< what broke
    Vec<dim>     position;                       ///< element centroid at breakage
    /// Crack normal at breakage: the contact normal; for a smooth joint the
    /// joint normal (seed 001).
    Vec<dim>     normal;
    double       size     = 0; ///< 2D: element length; 3D: 2 r_e
    double       gap      = 0; ///< element gap at breakage
    double       strength = 0; ///< strength exceeded [stress or force]
    std::int64_t step     = 0;
    double       time     = 0;
    /// Kept to follow the material after breakage (fistPkg §3.4): element
    /// centroid relative to the contact location, element gap and contact
    /// gap at breakage.
    Vec<dim> offset            = Vec<dim>::Zero();
    double   gap_break         = 0;
    double   contact_gap_break = 0;
  };

  /// Start or end of slip at a contact element.
  struct SlipRecord
  {
    std::int64_t id1 = 0, id2 = 0;
    int          element = 0;
    bool         started = false;
    std::int64_t step    = 0;
  };

  /// Where a contact lives: its group and index in it.
  struct ContactRef
  {
    int         group = -1;
    std::size_t index = 0;
  };

  template <int dim>
  struct ModelCheckpoint; // dem/io/checkpoint.cc: saves and restores the private state

  template <int dim>
  class Model
  {
  public:
    Particles<dim> particles;
    Walls<dim>     walls;

    // ---- contact laws ----------------------------------------------------
    /// Adds a group of contacts governed by law `Law` with parameters `p`
    /// (validated here, then the group constants derived: Law::prepare) and
    /// the optional property rule that completes each new contact's property
    /// block (dem/specimen/property_rules.h); returns the group id.
    template <class Law>
    int add_law(typename Law::Params p, const std::string &where = "contact law",
                typename ContactGroup<dim, Law>::Rule rule = {})
    {
      p.validate(where);
      Law::prepare(p);
      groups_.push_back(std::make_unique<ContactGroup<dim, Law>>(p, std::move(rule)));
      groups_.back()->suspend_breakage(breakage_suspended_);
      return static_cast<int>(groups_.size()) - 1;
    }
    /// Suspends (true) or resumes (false) bond breakage in every contact
    /// group, those added later included: while suspended, bonds carry any
    /// load elastically (ContactGroupBase::suspend_breakage); on resuming,
    /// a bond loaded beyond its strength breaks at the next step. Used to
    /// install a stress state before the strengths act (docs/architecture.md,
    /// "In-situ stress installation").
    void suspend_bond_breakage(bool s)
    {
      breakage_suspended_ = s;
      for (auto &g : groups_)
        g->suspend_breakage(s);
    }
    bool bond_breakage_suspended() const { return breakage_suspended_; }
    /// Group g as its law's type; InputError if it has another law.
    template <class Law>
    ContactGroup<dim, Law> &typed_group(int g)
    {
      auto *t = dynamic_cast<ContactGroup<dim, Law> *>(groups_.at(g).get());
      if (!t)
        throw InputError("contact group " + std::to_string(g) + " has law '" +
                         groups_[g]->law_name() + "', not '" + Law::name + "'");
      return *t;
    }
    int add_group(std::unique_ptr<ContactGroupBase<dim>> g);

    /// Law group that new contacts receive (-1: none created).
    void set_default_law(int ball_ball_group, int ball_wall_group);
    /// Optional rule for new ball-ball contacts: returns the law group for
    /// the pair (i, j), or -1 to use the default (e.g. the smooth-joint law
    /// for pairs across a joint plane, fistPkg §2.8). Called once per new
    /// contact, never per step.
    std::function<int(const Particles<dim> &, std::uint32_t, std::uint32_t)>
        new_contact_law;
    /// Same for new ball-wall contacts: returns the law group for particle i
    /// and facet k, or -1 to use the default wall law (e.g. frictionless
    /// plane-strain walls of a 3D slab next to a frictional interface).
    std::function<int(std::uint32_t, std::uint32_t)> new_wall_contact_law;

    /// Creates (or replaces) the contact between particles i and j with the
    /// law of `group`; returns where it lives.
    ContactRef install(std::uint32_t i, std::uint32_t j, int group);
    /// Same for particle i and wall facet k.
    ContactRef install_wall(std::uint32_t i, std::uint32_t k, int group);
    /// Moves an existing contact to another law group (re-installing it).
    ContactRef reassign(const ContactRef &c, int group);

    ContactGroupBase<dim>       &group(int g) { return *groups_[g]; }
    const ContactGroupBase<dim> &group(int g) const { return *groups_[g]; }
    int         n_groups() const { return static_cast<int>(groups_.size()); }
    std::size_t n_contacts() const;
    /// Looks up the contact between particles i and j (group -1 if none).
    ContactRef find(std::uint32_t i, std::uint32_t j, bool wall = false) const;

    // ---- stepping --------------------------------------------------------
    double   local_damping  = 0.7; ///< PFC local damping factor alpha
    double   skin           = 0;   ///< detection skin; 0: 0.1 * min radius
    double   safety_factor  = 0.8; ///< dt = safety * critical when automatic
    Vec<dim> gravity        = Vec<dim>::Zero();
    bool     check_timestep = true; ///< refuse dt above the critical estimate

    /// Fixed time step (> 0) or automatic (0: safety * critical, updated at
    /// every contact-detection pass).
    void   set_timestep(double dt);
    double timestep() const { return dt_; }
    /// Critical time step (memo §1.12): min over particles of
    /// sqrt(m / k_tran) and sqrt(I / k_rot) from the contact stiffnesses.
    double critical_timestep() const;
    /// Contacts whose gap is at most this [m] count in the critical time
    /// step as if closed (default 0: closed contacts only). Grains placed
    /// onto a wall free of force (a carved region's rim, coupling/) touch it
    /// across a gap of round-off size and close under the first load.
    double touching_gap = 0;

    /// Advances one step (detection when needed, forces, motion).
    void step();
    void cycle(std::int64_t n);

    std::int64_t step_count() const { return step_; }
    double       time() const { return time_; }

    // ---- monitoring ------------------------------------------------------
    double kinetic_energy() const;
    double strain_energy() const;
    double slip_energy() const;
    /// Mean unbalanced force over free particles divided by the mean contact
    /// force magnitude (PFC ratio-average, fistPkg §4.2.1).
    double unbalanced_ratio() const;

    std::vector<CrackRecord<dim>>                 cracks;
    std::function<void(const CrackRecord<dim> &)> on_crack;
    std::function<void(const SlipRecord &)>       on_slip;

    /// Work done on the assembly by prescribed motions, walls, external
    /// forces and gravity since the energy baseline was taken.
    double boundary_work() const { return work_in_; }
    /// Restarts the energy-balance check from the current state; call after
    /// changing the model by hand (radii, stiffnesses, prescribed overlaps).
    void reset_energy_baseline() { baseline_valid_ = false; }

    /// Reorders particles along a space-filling order of grid cells so that
    /// neighbours are close in memory (fewer cache misses in the contact
    /// loop). Indices change; particle ids do not. Opt-in: call it after
    /// setup when no particle indices are held outside the model.
    void reorder_by_cell();

    /// The cracks with their current geometry (memo footnote 3, fistPkg
    /// §3.4): position and normal follow the current contact plane of the
    /// two pieces (the centroid offset turns with the normal, by the minimal
    /// rotation from the normal at breakage) and the gap grows with the
    /// pieces' separation since breakage. `cracks` keeps the geometry at
    /// breakage; cracks whose particles were removed keep it too.
    std::vector<CrackRecord<dim>> current_cracks() const;

    /// Removes particles (contacts to them are deleted first).
    void remove_particles(const std::vector<char> &remove);
    /// Forces the next step to rebuild the contact set.
    void invalidate_contacts() { need_rebuild_ = true; }
    /// Rebuilds the contact set now (creates contacts for new pairs).
    void detect_contacts();

  private:
    friend struct ModelCheckpoint<dim>;
    void compute_forces();
    /// Contact forces and moments to the particles and wall vertices.
    void scatter_forces();
    /// Rebuilds the particle-to-contact incidence when the contacts changed.
    void update_incidence();
    struct Incidence
    {
      std::uint32_t group;   ///< law group
      std::uint32_t contact; ///< contact index << 1 | (1 if the particle is piece 2)
    };
    std::vector<std::uint32_t> incidence_start_; ///< CSR, N + 1
    std::vector<Incidence>     incidence_;
    std::vector<Incidence>     wall_incidence_; ///< ball-wall, in order
    std::vector<std::pair<const void *, std::uint64_t>> incidence_key_;
    void                     suppress_duplicate_wall_contacts(ContactGroupBase<dim> &g);
    std::vector<std::size_t> wall_scratch_;
    void                     integrate();
    bool                     rebuild_needed() const;
    std::uint64_t            key(std::uint32_t i, std::uint32_t j, bool wall) const
    {
      // Ball pairs are keyed independently of which end is piece 1, so a
      // renumbering (reorder_by_cell) never flips a contact's orientation.
      if (!wall && i > j)
        std::swap(i, j);
      return (static_cast<std::uint64_t>(i) << 32) | j | (wall ? (1ull << 63) : 0ull);
    }
    void erase(const ContactRef &c);
    /// Renumbers contact ends with old->new particle map and rebuilds index_.
    void remap_contacts(const std::vector<std::int64_t> &map);

    std::vector<std::unique_ptr<ContactGroupBase<dim>>> groups_;
    bool breakage_suspended_ = false; // suspend_bond_breakage
    std::unordered_map<std::uint64_t, ContactRef> index_;
    NeighborGrid<dim>                             grid_;
    std::vector<EventSink>                        sinks_;
    int                                           default_ball_ = -1, default_wall_ = -1;
    double                                        dt_           = 0;
    bool                                          auto_dt_      = true;
    bool                                          need_rebuild_ = true;
    std::vector<Vec<dim>>                         x_at_rebuild_, wall_at_rebuild_;
    std::int64_t                                  step_ = 0;
    double                                        time_ = 0;
    /// Kinetic-energy growth (common/growth_monitor.h); its last value and
    /// streak are checkpointed.
    instability::GrowthMonitor ke_growth_{instability::dem_kinetic_energy};
    bool                       baseline_valid_ = false;
    double                     energy0_ = 0, work_in_ = 0;
    void                       check_energy_balance();
  };
} // namespace demfem::dem
