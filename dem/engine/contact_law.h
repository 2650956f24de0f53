#pragma once
// The contract between the DEM engine and its contact laws
// (docs/architecture.md, "The contact-law contract").
//
// A law is a struct templated on dim with only static functions and two
// nested types:
//  - `Props`, the per-contact property block (memo §1.9 "properties": the
//    stiffnesses, strengths, radius multiplier, reference gap, initial
//    microstructural type, ...): plain doubles, one block per contact at a
//    fixed stride next to the state, set once when the contact is installed
//    (the group's defaults, then the group's property rule, e.g. the
//    deformability method kn = E*/L of memo Eq. 40 and the material's
//    strength draws), written into checkpoints with the state, and readable
//    and (where the memo marks them modifiable) settable during a run;
//  - `Params`, the group-wide parameters, deriving from Props: the Props part
//    is the default block a new contact receives (PFC's contact-model
//    assignment), the rest is shared by every contact of the group (element
//    counts, install flags) together with constants derived from it once
//    when the group is made (`prepare`).
// The per-contact state is a block of `state_size(p)` doubles owned by the
// engine (fixed stride per group). The engine resolves the contact plane and
// the relative-motion increments (memo §1.3, Eq. 2-11) and hands them to
// `update` in contact-plane components; the law returns the contact force
// and moment in the same components (memo Eq. 58).
// `update` is called every step for every existing contact, active or not,
// so that laws can keep tracking relative motion (e.g. the flat-joint surface
// gap); `active` is informational (memo §1.6) and `deletable` tells the
// contact detection it may drop the contact when the pair leaves the skin.
// Laws never allocate per step and are dispatched once per law group
// (the contact loop is templated on the law), never per contact.
//
// Required members of a law L<dim>:
//   static constexpr const char *name;              registry name
//   static constexpr BondType    bond_type;         what its crack records are
//   struct Props { double ...; };                   per-contact block
//   struct Params : Props { ...; void validate(const std::string &where) const; };
//   static void prepare(Params &);                  group constants, once
//   static void derive(const Params &, Props &);    per-contact constants,
//                                                   after the block is set
//   static Props unbreakable(const Props &);        the block with infinite
//                                                   bond strengths (a law
//                                                   without bond: the block)
//   static const std::vector<PropertyField<Props>> &properties();
//   static int  state_size(const Params &);
//   static void install(const Params &, const Props &, const ContactGeometry<dim> &,
//                       double *state);
//   static void update(const Params &, const Props &, const ContactStep<dim> &,
//                      double *state, ContactForce &force, EventSink &events);
//   static bool active(const Params &, const Props &, const double *state, double gap);
//   static bool deletable(const Params &, const Props &, const double *state, double gap);
//   static ContactStiffness stiffness(const Params &, const Props &,
//                                     const ContactGeometry<dim> &, const double *state);
//   static double strain_energy(const Params &, const Props &, const double *state);
//   static double slip_energy(const Params &, const Props &, const double *state);
#include "dem/engine/types.h"

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace demfem::dem
{
  /// What a crack record broke (fistPkg §3.4 counts material cracks by bond
  /// type; smooth-joint breakages are joint cracks, not material cracks).
  enum class BondType : int
  {
    none          = -1, ///< the law has no bond (linear)
    contact_bond  = 0,
    parallel_bond = 1,
    flat_joint    = 2,
    smooth_joint  = 3
  };
  constexpr int n_bond_types = 4;
  /// "contact_bond", "parallel_bond", "flat_joint", "smooth_joint" (or "none").
  const char *bond_type_name(BondType t);

  /// One named per-contact property of a law (PFC keyword), read and set
  /// through the contact groups (memo §1.9, Table 5 "Modifiable").
  template <class Props>
  struct PropertyField
  {
    const char *name;
    double (*get)(const Props &);
    void (*set)(Props &, double);
    bool   modifiable; ///< may be changed while cycling
    double lo, hi;     ///< allowed closed range
  };

  /// The property block of a law as doubles (checkpoints, VTK); every Props
  /// is a trivially copyable block of doubles.
  template <class Props>
  constexpr int props_doubles()
  {
    static_assert(std::is_trivially_copyable_v<Props> &&
                      sizeof(Props) % sizeof(double) == 0,
                  "a law's Props must be a trivially copyable block of doubles");
    return static_cast<int>(sizeof(Props) / sizeof(double));
  }
  /// Contact-plane geometry (memo §1.3.1, Eq. 2-5). All vectors global.
  template <int dim>
  struct ContactGeometry
  {
    Vec<dim> n;  ///< unit normal, from piece 1 towards piece 2
    Vec<dim> s;  ///< s axis (3D: tracked by memo Eq. 5; 2D: unused, s = -k)
    Vec<dim> t;  ///< t axis (2D: t = k x n, memo Eq. 4; 3D: n = s x t)
    Vec<dim> xc; ///< contact location (memo Eq. 2)
    double   gap = 0;      ///< contact gap g_c, > 0 open
    double   R1  = 0;      ///< radius of piece 1
    double   R2  = 0;      ///< radius of piece 2 (0 for ball-wall)
    bool     ball_wall = false;

    /// min(R1, R2) for ball-ball, R1 for ball-wall (memo Eq. 30).
    double min_radius() const { return ball_wall ? R1 : (R1 < R2 ? R1 : R2); }
    /// L of memo Eq. 40: R1 + R2 (ball-ball) or R1 (ball-wall).
    double length() const { return ball_wall ? R1 : R1 + R2; }
  };

  /// Geometry plus the relative-motion increments of one step, in
  /// contact-plane components (memo Eq. 11). 2D: d_ss = d_twist = d_bt = 0 and
  /// d_bs = -dtheta_k (memo: theta_bk = -theta_bs).
  template <int dim>
  struct ContactStep : ContactGeometry<dim>
  {
    double d_n     = 0; ///< normal displacement increment, > 0 opening
    double d_ss    = 0; ///< shear displacement increment along s
    double d_st    = 0; ///< shear displacement increment along t
    double d_twist = 0; ///< twist rotation increment about n
    double d_bs    = 0; ///< bend rotation increment about s
    double d_bt    = 0; ///< bend rotation increment about t
    double dt      = 0; ///< time step
  };

  /// Contact force and moment in contact-plane components (memo Eq. 58):
  /// F_c = -Fn n + Fss s + Fst t, M_c = Mt n + Mbs s + Mbt t, acting on
  /// piece 2 (piece 1 receives the opposite). Fn > 0 is tension.
  struct ContactForce
  {
    double Fn = 0, Fss = 0, Fst = 0, Mt = 0, Mbs = 0, Mbt = 0;
  };

  /// Translational and rotational stiffnesses for the time-step estimate
  /// (memo §1.12, Eq. 41-42).
  struct ContactStiffness
  {
    double kn = 0, ks = 0, kb = 0, kt = 0;
  };

  /// Something that happened inside a law during `update`.
  struct LawEvent
  {
    enum Kind : int
    {
      bond_break = 0,
      slip_start = 1,
      slip_end   = 2
    };
    Kind   kind    = bond_break;
    int    element = 0;  ///< element index (0-based); 0 for single-element laws
    int    mode    = 0;  ///< bond_break: 0 tension, 1 shear
    double r_s     = 0;  ///< element centroid, contact-plane s coordinate
    double r_t     = 0;  ///< element centroid, contact-plane t coordinate
    double size    = 0;  ///< crack size (fistPkg §3.4): element length / 2 r_e
    double gap     = 0;  ///< element gap at the time of the event
    double strength = 0; ///< strength exceeded (stress), for reporting
    /// Crack normal when it is not the contact normal (smooth joint: the
    /// joint normal, seed 001); global components.
    bool   has_normal = false;
    double normal[3]  = {0, 0, 0};
  };

  /// Per-thread collector of law events; the engine sets `contact` before
  /// each update and turns the events into crack records afterwards.
  struct EventSink
  {
    std::size_t                                   contact = 0;
    std::vector<std::pair<std::size_t, LawEvent>> events;
    void push(const LawEvent &e) { events.emplace_back(contact, e); }
  };
} // namespace demfem::dem
