#pragma once
// Contacts grouped by law: one group per law per material (plus the walls),
// whatever the property distributions. Per-contact data common to every law
// is kept in structure-of-arrays form in ContactGroupBase; the law's
// per-contact property block and its state live in ContactGroup<dim, Law>,
// each at a fixed stride (docs/architecture.md, "The contact-law contract"). The
// only virtual call is one `compute` per group per step: the contact loop
// inside is compiled for the concrete law.
#include "dem/engine/contact_law.h"
#include "dem/engine/particles.h"
#include "dem/engine/walls.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace demfem::dem
{
  /// Loops shorter than this run on one thread (tests may lower it): below it the cost of
  /// waking the OpenMP team exceeds the work (measured: a 5-grain model ran 40x slower on
  /// 2 threads than on 1).
  inline std::size_t parallel_threshold = 2048;

  template <int dim>
  class ContactGroupBase
  {
  public:
    virtual ~ContactGroupBase() = default;

    virtual const char *law_name() const  = 0;
    virtual int         stride() const    = 0;
    virtual BondType    bond_type() const = 0;

    // ---- per-contact properties (memo §1.9) --------------------------------
    /// The law's property keywords (PFC names, e.g. "fj_kn").
    virtual std::vector<std::string> property_names() const = 0;
    /// Whether the keyword may be changed while cycling (memo Table 5).
    virtual bool property_modifiable(const std::string &name) const = 0;
    /// Property `name` of contact k; InputError for an unknown name.
    virtual double property(std::size_t k, const std::string &name) const = 0;
    /// Sets a modifiable property of contact k (derived constants follow);
    /// InputError naming the keyword for an unknown or non-modifiable name
    /// or a value outside its range.
    virtual void set_property(std::size_t k, const std::string &name, double value) = 0;
    /// Makes contact k's bond unbreakable for good (its strengths infinite,
    /// Law::unbreakable): a loading frame's neighbourhood, e.g. the outer
    /// band of the full-DEM tunnel reference. Set-up only, not per step.
    virtual void make_unbreakable(std::size_t k) = 0;
    /// Doubles per contact of the property block.
    virtual int props_stride() const = 0;
    /// All property blocks (size() * props_stride() doubles), for
    /// checkpoints, and their restoration.
    virtual std::vector<double> props_data() const                           = 0;
    virtual void                set_props_data(const std::vector<double> &d) = 0;

    /// Adds a contact between particle i and particle j (or facet j when
    /// `wall`), resolves its plane from the current positions and installs
    /// the law (memo Eq. 29-31). Returns its index in the group.
    std::size_t add(std::uint32_t i, std::uint32_t j, bool wall, const Particles<dim> &p,
                    const Walls<dim> &w);
    /// Removes contact k by moving the last contact into its slot.
    virtual void remove(std::size_t k);

    /// Updates the contact plane, the relative increments and the law for
    /// every contact (threaded); fills force_global/moment_global/xc.
    virtual void compute(const Particles<dim> &p, const Walls<dim> &w, double dt,
                         std::vector<EventSink> &sinks) = 0;

    virtual bool             deletable(std::size_t k) const                          = 0;
    virtual bool             active(std::size_t k) const                             = 0;
    virtual ContactStiffness stiffness(std::size_t k, const Particles<dim> &p) const = 0;
    virtual double           strain_energy(std::size_t k) const                      = 0;
    virtual double           slip_energy(std::size_t k) const                        = 0;
    /// Adds each active contact's translational stiffness max(kn, ks) to
    /// kt[particle] and its rotational stiffness max(kb, kt) + ks |arm|^2 to
    /// kr[particle] (memo §1.12; input of Model::critical_timestep). A
    /// contact whose gap is at most `touching_gap` counts as active
    /// (Model::touching_gap).
    virtual void accumulate_stiffness(const Particles<dim> &p, std::vector<double> &kt,
                                      std::vector<double> &kr,
                                      double               touching_gap) const = 0;
    /// Sum of the strain energy of all contacts of the group (the values
    /// evaluated by the last `compute` when requested and still current).
    virtual double total_strain_energy() const = 0;
    /// Asks the next `compute` to evaluate each contact's strain energy right
    /// after its law update, while the state block is in cache (Model::step
    /// does this on the steps of the energy-balance check; a separate pass
    /// over all states cost ~5 % of a 3D flat-joint run).
    void request_strain_energy() { energy_requested_ = true; }
    /// Bond breakage suspended: while true, `compute` hands each law its
    /// block with infinite bond strengths (Law::unbreakable), so bonds stay
    /// intact whatever their load; the blocks themselves are not touched.
    /// For installing a stress state elastically before the strengths act
    /// (docs/architecture.md, "In-situ stress installation").
    void    suspend_breakage(bool s) { breakage_suspended_ = s; }
    bool    breakage_suspended() const { return breakage_suspended_; }
    double *state(std::size_t k)
    {
      energy_fresh_ = false; // the caller may change the state
      return &state_[k * stride()];
    }
    const double *state(std::size_t k) const { return &state_[k * stride()]; }
    /// The whole law-state block (size() * stride() doubles), for checkpoints.
    std::vector<double> &state_data()
    {
      energy_fresh_ = false;
      return state_;
    }
    const std::vector<double> &state_data() const { return state_; }

    std::size_t size() const { return end1.size(); }

    /// Changes whenever the list of contacts or their ends change (add,
    /// remove, renumbering, restore): the model's particle-to-contact
    /// incidence is rebuilt only then.
    std::uint64_t topology_version() const { return topology_; }
    void          topology_changed() { ++topology_; }

    /// Resolves the contact plane of contact k from the current positions
    /// (memo Eq. 2; the s axis is the stored one, not updated here).
    ContactGeometry<dim> geometry(std::size_t k, const Particles<dim> &p,
                                  const Walls<dim>        &w,
                                  std::array<double, dim> *facet_weights = nullptr) const;

    // Per-contact data (structure of arrays).
    std::vector<std::uint32_t>           end1, end2; ///< particle, particle-or-facet
    std::vector<char>                    is_wall;
    std::vector<Vec<dim>>                s_axis;        ///< 3D: tracked s axis (Eq. 5)
    std::vector<Vec<dim>>                n_prev;        ///< normal of the previous step
    std::vector<Vec<dim>>                xc;            ///< contact location
    std::vector<double>                  gap;           ///< contact gap
    std::vector<ContactForce>            local_force;   ///< contact-plane components
    std::vector<Vec<dim>>                force;         ///< F_c (on piece 2), global
    std::vector<RotVec<dim>>             moment;        ///< M_c (on piece 2), global
    std::vector<std::array<double, dim>> facet_weights; ///< ball-wall: barycentric

  protected:
    virtual void        install(std::size_t k, const ContactGeometry<dim> &g) = 0;
    std::vector<double> state_;
    /// Per-contact strain energy from the last `compute` (valid while
    /// energy_fresh_: cleared by add/remove and non-const state access).
    std::vector<double> energy_;
    bool                energy_requested_ = false, energy_fresh_ = false;
    std::uint64_t       topology_           = 0;
    bool                breakage_suspended_ = false;
  };

  template <int dim, class Law>
  class ContactGroup final : public ContactGroupBase<dim>
  {
  public:
    using Params = typename Law::Params;
    using Props  = typename Law::Props;
    /// Property rule: completes a new contact's block (which starts as the
    /// group's defaults, the Props part of Params) from its geometry, e.g.
    /// the deformability method and strength draws (dem/specimen/property_rules.h).
    /// Called once per installed contact, never per step.
    using Rule = std::function<void(const ContactGeometry<dim> &, Props &)>;

    /// `p` must have been prepared (Law::prepare; Model::add_law does it).
    explicit ContactGroup(const Params &p, Rule r = {})
        : params(p)
        , rule(std::move(r))
        , stride_(Law::state_size(p))
    {
    }

    const char *law_name() const override { return Law::name; }
    int         stride() const override { return stride_; }
    BondType    bond_type() const override { return Law::bond_type; }

    Props       &properties(std::size_t k) { return props_[k]; }
    const Props &properties(std::size_t k) const { return props_[k]; }
    /// Installs contact k again from its current property block: for the
    /// properties fixed before cycling (memo Table 5 note 1: radius
    /// multiplier, initial gap), which genesis sets after installation.
    void reinstall(std::size_t k, const Particles<dim> &p, const Walls<dim> &w)
    {
      Law::derive(params, props_[k]);
      Law::install(params, props_[k], this->geometry(k, p, w), this->state(k));
    }

    std::vector<std::string> property_names() const override
    {
      std::vector<std::string> n;
      for (const auto &f : Law::properties())
        n.push_back(f.name);
      return n;
    }
    bool property_modifiable(const std::string &name) const override
    {
      return field(name).modifiable;
    }
    double property(std::size_t k, const std::string &name) const override
    {
      return field(name).get(props_.at(k));
    }
    void set_property(std::size_t k, const std::string &name, double value) override
    {
      const auto &f = field(name);
      if (!f.modifiable)
        throw InputError(std::string(Law::name) + " property '" + name +
                         "' is fixed once the contact is installed (memo Table 5)");
      check_range(std::string(Law::name) + " contact property", name, value, f.lo, f.hi);
      f.set(props_.at(k), value);
      Law::derive(params, props_[k]);
      this->energy_fresh_ = false;
    }
    void make_unbreakable(std::size_t k) override
    {
      props_.at(k)        = Law::unbreakable(props_[k]);
      this->energy_fresh_ = false;
    }
    int                 props_stride() const override { return props_doubles<Props>(); }
    std::vector<double> props_data() const override
    {
      std::vector<double> d(props_.size() * props_doubles<Props>());
      if (!d.empty())
        std::memcpy(d.data(), props_.data(), sizeof(double) * d.size());
      return d;
    }
    void set_props_data(const std::vector<double> &d) override
    {
      props_.resize(d.size() / props_doubles<Props>());
      if (!d.empty())
        std::memcpy(static_cast<void *>(props_.data()), d.data(),
                    sizeof(double) * d.size());
      this->energy_fresh_ = false;
    }

    void compute(const Particles<dim> &p, const Walls<dim> &w, double dt,
                 std::vector<EventSink> &sinks) override;

    bool active(std::size_t k) const override
    {
      return Law::active(params, props_[k], this->state(k), this->gap[k]);
    }
    bool deletable(std::size_t k) const override
    {
      return Law::deletable(params, props_[k], this->state(k), this->gap[k]);
    }
    ContactStiffness stiffness(std::size_t k, const Particles<dim> &p) const override
    {
      ContactGeometry<dim> g;
      g.R1        = p.radius[this->end1[k]];
      g.R2        = this->is_wall[k] ? 0.0 : p.radius[this->end2[k]];
      g.ball_wall = this->is_wall[k];
      return Law::stiffness(params, props_[k], g, this->state(k));
    }
    double strain_energy(std::size_t k) const override
    {
      return Law::strain_energy(params, props_[k], this->state(k));
    }
    void accumulate_stiffness(const Particles<dim> &p, std::vector<double> &kt,
                              std::vector<double> &kr, double touching_gap) const override
    {
      for (std::size_t k = 0; k < this->size(); ++k)
        {
          if (!active(k) && !(this->gap[k] <= touching_gap))
            continue;
          const ContactStiffness s   = stiffness(k, p);
          const double           ktr = std::max(s.kn, s.ks);
          const double           kro = std::max(s.kb, s.kt);
          const std::uint32_t    i   = this->end1[k];
          kt[i] += ktr;
          kr[i] += kro + s.ks * (this->xc[k] - p.x[i]).squaredNorm();
          if (!this->is_wall[k])
            {
              const std::uint32_t j = this->end2[k];
              kt[j] += ktr;
              kr[j] += kro + s.ks * (this->xc[k] - p.x[j]).squaredNorm();
            }
        }
    }
    double total_strain_energy() const override
    {
      const bool fresh = this->energy_fresh_ && this->energy_.size() == this->size();
      double     e     = 0; // summed in contact order: independent of the threads
      for (std::size_t k = 0; k < this->size(); ++k)
        e += fresh ? this->energy_[k]
                   : Law::strain_energy(params, props_[k], this->state(k));
      return e;
    }
    double slip_energy(std::size_t k) const override
    {
      return Law::slip_energy(params, props_[k], this->state(k));
    }
    void remove(std::size_t k) override
    {
      if (k + 1 != props_.size())
        props_[k] = props_.back();
      props_.pop_back();
      ContactGroupBase<dim>::remove(k);
    }

    const Params params;
    const Rule   rule;

  protected:
    /// The new contact's block: the group's defaults, then the rule, then
    /// the derived constants (memo §1.10); then the law's installation.
    void install(std::size_t k, const ContactGeometry<dim> &g) override
    {
      if (props_.size() <= k)
        props_.resize(k + 1);
      props_[k] = static_cast<const Props &>(params);
      if (rule)
        rule(g, props_[k]);
      Law::derive(params, props_[k]);
      Law::install(params, props_[k], g, this->state(k));
    }

  private:
    /// Contact plane and relative increments of contact k for this step
    /// (memo §1.3, Eq. 2-11); updates the tracked s axis and n_prev.
    void kinematics(std::size_t k, const Particles<dim> &p, const Walls<dim> &w,
                    double dt, ContactStep<dim> &st);
    const PropertyField<Props> &field(const std::string &name) const
    {
      for (const auto &f : Law::properties())
        if (name == f.name)
          return f;
      std::string allowed;
      for (const auto &f : Law::properties())
        allowed += std::string(" ") + f.name;
      throw InputError(std::string(Law::name) + ": unknown contact property '" + name +
                       "'; allowed:" + allowed);
    }
    std::vector<Props> props_; ///< per-contact property blocks
    const int          stride_;
  };

  //------------------------------------------------------------------------
  // Kinematics shared by all laws (memo §1.3).

  /// Initial s axis (memo §1.3.1): projection of global x onto the contact
  /// plane, or of global y when x is (nearly) parallel to n.
  template <int dim>
  Vec<dim> initial_s_axis(const Vec<dim> &n);

  // Inline: called per contact per step from the templated contact loop,
  // where the compiler fuses it with the kinematics (out of line it cost
  // ~8 % of a 3D run plus a store-forwarding stall on the returned struct).
  template <int dim>
  inline __attribute__((always_inline)) ContactGeometry<dim>
  ContactGroupBase<dim>::geometry(std::size_t k, const Particles<dim> &p,
                                  const Walls<dim>        &w,
                                  std::array<double, dim> *weights) const
  {
    ContactGeometry<dim> g;
    const std::uint32_t  i = end1[k], j = end2[k];
    g.R1 = p.radius[i];
    Vec<dim> d;
    if (is_wall[k])
      {
        std::array<double, dim> wgt;
        d           = w.closest_point(j, p.x[i], wgt) - p.x[i];
        g.R2        = 0;
        g.ball_wall = true;
        if (weights)
          *weights = wgt;
      }
    else
      {
        d    = p.x[j] - p.x[i];
        g.R2 = p.radius[j];
      }
    const double dist = d.norm();
    // Coincident centres have no normal; keep the previous one.
    g.n   = dist > 0 ? Vec<dim>(d / dist) : n_prev[k];
    g.gap = dist - g.R1 - g.R2;
    g.xc  = p.x[i] + (g.R1 + 0.5 * g.gap) * g.n; // memo Eq. 2
    if constexpr (dim == 3)
      {
        g.s = s_axis[k];
        g.t = g.n.cross(g.s);
      }
    else
      {
        g.s.setZero();
        g.t = Vec<2>(-g.n[1], g.n[0]);
      }
    return g;
  }

  template <int dim, class Law>
  inline __attribute__((always_inline)) void ContactGroup<dim, Law>::kinematics(
      std::size_t k, const Particles<dim> &p, const Walls<dim> &w, double dt,
      ContactStep<dim> &st)
  {
    static_cast<ContactGeometry<dim> &>(st) =
        this->geometry(k, p, w, &this->facet_weights[k]);
    const std::uint32_t i = this->end1[k], j = this->end2[k];
    // Contact-plane axes. 3D: memo Eq. 5 (rotate the old s axis about the
    // line common to the old and new planes, then about the new normal by
    // the mean spin of the two pieces), re-orthonormalised against n.
    if constexpr (dim == 3)
      {
        const Vec<3> &nn = st.n, &no = this->n_prev[k];
        Vec<3>        s1 = this->s_axis[k] - this->s_axis[k].cross(no.cross(nn));
        RotVec<3>     w2 = st.ball_wall ? RotVec<3>::Zero() : p.w[j];
        const Vec<3>  wt = (0.5 * (p.w[i] + w2).dot(nn)) * nn;
        Vec<3>        s2 = s1 - s1.cross(wt * dt);
        s2 -= s2.dot(nn) * nn;
        if (s2.squaredNorm() < 1e-24)
          s2 = initial_s_axis<3>(nn);
        st.s            = s2.normalized();
        st.t            = nn.cross(st.s);
        this->s_axis[k] = st.s;
      }
    else
      {
        st.s.setZero();
        st.t = Vec<2>(-st.n[1], st.n[0]); // t = k x n (memo Eq. 4)
      }
    this->n_prev[k] = st.n;
    // Relative velocity of the surfaces at the contact (memo Eq. 7-8).
    Vec<dim>       v1 = p.v[i], v2 = Vec<dim>::Zero();
    RotVec<dim>    w1 = p.w[i], w2 = RotVec<dim>::Zero();
    const Vec<dim> r1 = st.xc - p.x[i];
    if constexpr (dim == 3)
      v1 += w1.cross(r1);
    else
      v1 += w1[0] * Vec<2>(-r1[1], r1[0]);
    if (!st.ball_wall)
      {
        w2                = p.w[j];
        const Vec<dim> r2 = st.xc - p.x[j];
        v2                = p.v[j];
        if constexpr (dim == 3)
          v2 += w2.cross(r2);
        else
          v2 += w2[0] * Vec<2>(-r2[1], r2[0]);
      }
    else
      for (int a = 0; a < dim; ++a)
        v2 += this->facet_weights[k][a] * w.vertex_velocity[w.facet[j][a]];
    // Increments (memo Eq. 9-11), in contact-plane components.
    const Vec<dim>    dd  = (v2 - v1) * dt;
    const RotVec<dim> dth = (w2 - w1) * dt;
    st.dt                 = dt;
    st.d_n                = dd.dot(st.n);
    st.d_st               = dd.dot(st.t);
    if constexpr (dim == 3)
      {
        st.d_ss    = dd.dot(st.s);
        st.d_twist = dth.dot(st.n);
        st.d_bs    = dth.dot(st.s);
        st.d_bt    = dth.dot(st.t);
      }
    else
      st.d_bs = -dth[0]; // s = -k, so theta_bs = -theta_k (memo Table 1)
  }

  template <int dim, class Law>
  void ContactGroup<dim, Law>::compute(const Particles<dim> &p, const Walls<dim> &w,
                                       double dt, std::vector<EventSink> &sinks)
  {
    const std::size_t nc          = this->size();
    const bool        want_energy = this->energy_requested_;
    this->energy_requested_       = false;
    this->energy_fresh_           = false;
    if (want_energy)
      this->energy_.resize(nc);
    double *const      state_block = this->state_.data();
    const Props *const props_block = props_.data();
    const int          n_state     = stride_;
    const bool         unbreakable = this->breakage_suspended_;
    // Contacts go in blocks: first the kinematics of the whole block, whose
    // iterations are independent so the out-of-order core overlaps their
    // sqrt/division latency chains (one contact at a time, the long law
    // update between two of them hid nothing), then the law updates.
    constexpr std::size_t block    = 16;
    const std::size_t     n_blocks = (nc + block - 1) / block;
#pragma omp parallel for schedule(static) if (nc > parallel_threshold)
    for (std::size_t b = 0; b < n_blocks; ++b)
      {
        const std::size_t k0 = b * block, k1 = std::min(nc, k0 + block);
        ContactStep<dim>  steps[block];
        for (std::size_t k = k0; k < k1; ++k)
          kinematics(k, p, w, dt, steps[k - k0]);
        EventSink &sink = sinks[omp_get_thread_num()];
        for (std::size_t k = k0; k < k1; ++k)
          {
            const ContactStep<dim> &st    = steps[k - k0];
            double *const           state = state_block + k * n_state;
            sink.contact                  = k;
            ContactForce &f               = this->local_force[k];
            const Props  &q               = props_block[k];
            if (unbreakable) // a copy only while suspended (not the hot path)
              Law::update(params, Law::unbreakable(q), st, state, f, sink);
            else
              Law::update(params, q, st, state, f, sink);
            if (want_energy)
              this->energy_[k] = Law::strain_energy(params, q, state);
            // Global force and moment on piece 2 (memo Eq. 58).
            this->force[k] = -f.Fn * st.n + f.Fst * st.t;
            if constexpr (dim == 3)
              {
                this->force[k] += f.Fss * st.s;
                this->moment[k] = f.Mt * st.n + f.Mbs * st.s + f.Mbt * st.t;
              }
            else
              this->moment[k][0] = -f.Mbs; // s = -k
            this->xc[k]  = st.xc;
            this->gap[k] = st.gap;
          }
      }
    this->energy_fresh_ = want_energy;
  }
} // namespace demfem::dem
