#include "dem/io/checkpoint.h"

#include "dem/io/hdf5_io.h"
#include "dem/laws/contact_bond_law.h"
#include "dem/laws/flat_joint_law.h"
#include "dem/laws/linear_law.h"
#include "dem/laws/parallel_bond_law.h"
#include "dem/laws/smooth_joint_law.h"

#include <cstring>
#include <mutex>
#include <sstream>
#include <type_traits>
#include <utility>

namespace demfem::dem
{
  using namespace hdf5io;

  namespace
  {
    constexpr const char *format_name = "demfem DEM checkpoint";
    // 2: flat-joint element codes stored as bytes (FlatJointLaw state layout).
    // 3: per-contact property blocks ("props" per group, "props_names") and
    //    the crack type.
    // 4: Fletcher32 checksums on every dataset, strings stored as checksummed
    //    bytes, a checksum trailer over the whole file (dem/io/hdf5_io.h).
    constexpr int format_version = 5; // 5: /state (named state of the caller's objects)

    // ----------------------------------------------------------------------
    // Law parameters. Params are stored as an opaque blob (with its size) and
    // as named values (PFC keywords, as in dem/engine/law_registry.cc). The restart
    // check compares the named values: a byte comparison would also compare
    // the padding after the bool flags, which copies leave indeterminate.

    template <class Law>
    struct ParamFields;

    template <int dim>
    struct ParamFields<LinearLaw<dim>>
    {
      // The linear block, also inside the contact and parallel bonds.
      using P = typename LinearLaw<dim>::Props;
      static std::vector<std::pair<std::string, double>> get(const P &p)
      {
        return {
            {"kn", p.kn}, {"ks", p.ks}, {"fric", p.friction}, {"rgap", p.reference_gap}};
      }
    };

    template <int dim>
    struct ParamFields<ContactBondLaw<dim>>
    {
      using P = typename ContactBondLaw<dim>::Params;
      static std::vector<std::pair<std::string, double>> get(const P &p)
      {
        auto f = ParamFields<LinearLaw<dim>>::get(p.linear);
        f.insert(f.end(), {{"cb_tenf", p.cb_tenf},
                           {"cb_shearf", p.cb_shearf},
                           {"cb_bonded", p.bonded ? 1.0 : 0.0}});
        return f;
      }
    };

    template <int dim>
    struct ParamFields<ParallelBondLaw<dim>>
    {
      using P = typename ParallelBondLaw<dim>::Params;
      static std::vector<std::pair<std::string, double>> get(const P &p)
      {
        auto f = ParamFields<LinearLaw<dim>>::get(p.linear);
        f.insert(f.end(), {{"pb_kn", p.pb_kn},
                           {"pb_ks", p.pb_ks},
                           {"pb_rmul", p.pb_rmul},
                           {"pb_mcf", p.pb_mcf},
                           {"pb_ten", p.pb_ten},
                           {"pb_coh", p.pb_coh},
                           {"pb_fa", p.pb_fa},
                           {"pb_bonded", p.bonded ? 1.0 : 0.0}});
        return f;
      }
    };

    template <int dim>
    struct ParamFields<FlatJointLaw<dim>>
    {
      using P = typename FlatJointLaw<dim>::Params;
      static std::vector<std::pair<std::string, double>> get(const P &p)
      {
        return {{"fj_Nr", double(p.Nr)},
                {"fj_Nal", double(p.Nal)},
                {"fj_rmul", p.rmul},
                {"fj_gap0", p.gap0},
                {"fj_kn", p.kn},
                {"fj_ks", p.ks},
                {"fj_fric", p.fric},
                {"fj_ten", p.ten},
                {"fj_coh", p.coh},
                {"fj_fa", p.fa},
                {"fj_bonded", p.bonded ? 1.0 : 0.0}};
      }
    };

    template <int dim>
    struct ParamFields<SmoothJointLaw<dim>>
    {
      using P = typename SmoothJointLaw<dim>::Params;
      static std::vector<std::pair<std::string, double>> get(const P &p)
      {
        return {{"sj_kn", p.sj_kn},
                {"sj_ks", p.sj_ks},
                {"sj_fric", p.sj_fric},
                {"sj_da", p.sj_da},
                {"sj_ten", p.sj_ten},
                {"sj_coh", p.sj_coh},
                {"sj_fa", p.sj_fa},
                {"sj_rmul", p.sj_rmul},
                {"dip", p.dip},
                {"ddir", p.ddir},
                {"sj_large", p.sj_large ? 1.0 : 0.0},
                {"sj_bonded", p.bonded ? 1.0 : 0.0}};
      }
    };

    struct ParamsRecord
    {
      std::vector<std::uint8_t> bytes; ///< the Params object, sizeof(Params) bytes
      std::vector<std::string>  names;
      std::vector<double>       values;
    };

    template <int dim, class Law>
    bool params_of(const ContactGroupBase<dim> &g, ParamsRecord &out)
    {
      using P = typename Law::Params;
      static_assert(std::is_trivially_copyable_v<P>,
                    "law parameters must be trivially copyable");
      const auto *cg = dynamic_cast<const ContactGroup<dim, Law> *>(&g);
      if (!cg)
        return false;
      out.bytes.resize(sizeof(P));
      std::memcpy(out.bytes.data(), &cg->params, sizeof(P));
      for (const auto &[n, v] : ParamFields<Law>::get(cg->params))
        out.names.push_back(n), out.values.push_back(v);
      return true;
    }

    /// The parameters of group g, whatever its law (one of the registered laws).
    template <int dim, class... Laws>
    ParamsRecord params_record_of(const ContactGroupBase<dim> &g, int index, const Ctx &c)
    {
      ParamsRecord r;
      if (!(params_of<dim, Laws>(g, r) || ...))
        c.fail("contact group " + std::to_string(index) + " has law '" + g.law_name() +
               "', which checkpoints do not know");
      return r;
    }

    template <int dim>
    ParamsRecord params_record(const ContactGroupBase<dim> &g, int index, const Ctx &c)
    {
      return params_record_of<dim, LinearLaw<dim>, ContactBondLaw<dim>,
                              ParallelBondLaw<dim>, FlatJointLaw<dim>,
                              SmoothJointLaw<dim>>(g, index, c);
    }

    std::string fmt(double v)
    {
      std::ostringstream s;
      s.precision(17);
      s << v;
      return s.str();
    }

  } // namespace

  // ------------------------------------------------------------------------
  // The model's state, private members included (friend of Model).

  template <int dim>
  struct ModelCheckpoint
  {
    static constexpr int rd = rot_dim<dim>;
    using Cr                = CrackRecord<dim>;

    static void write(const Model<dim> &m, hid_t file, const Ctx &c)
    {
      write_scalar<int>(c, file, "dim", dim);
      // --- model scalars and detection state
      {
        Handle g = make_group(c, file, "model");
        write_scalar<std::int64_t>(c, g, "step", m.step_);
        write_scalar<std::int64_t>(c, g, "next_particle_id",
                                   m.particles.next_particle_id());
        write_scalar<double>(c, g, "time", m.time_);
        write_scalar<double>(c, g, "timestep", m.dt_);
        write_scalar<std::uint8_t>(c, g, "auto_timestep", m.auto_dt_);
        write_scalar<std::uint8_t>(c, g, "need_rebuild", m.need_rebuild_);
        write_scalar<int>(c, g, "default_ball_group", m.default_ball_);
        write_scalar<int>(c, g, "default_wall_group", m.default_wall_);
        write_scalar<double>(c, g, "local_damping", m.local_damping);
        write_scalar<double>(c, g, "skin", m.skin);
        write_scalar<double>(c, g, "safety_factor", m.safety_factor);
        write_scalar<std::uint8_t>(c, g, "check_timestep", m.check_timestep);
        write_data<double>(c, g, "gravity", m.gravity.data(), dim, 1);
        write_rows<double>(c, g, "x_at_rebuild", m.x_at_rebuild_);
        write_rows<double>(c, g, "wall_at_rebuild", m.wall_at_rebuild_);
        // energy monitor (memo §1.12 stability checks)
        write_scalar<double>(c, g, "last_kinetic_energy", m.ke_growth_.last);
        write_scalar<int>(c, g, "growth_steps", m.ke_growth_.streak);
        write_scalar<std::uint8_t>(c, g, "baseline_valid", m.baseline_valid_);
        write_scalar<double>(c, g, "energy0", m.energy0_);
        write_scalar<double>(c, g, "work_in", m.work_in_);
      }
      // --- particles
      {
        const auto &P = m.particles;
        Handle      g = make_group(c, file, "particles");
        write_rows<double>(c, g, "x", P.x);
        write_rows<double>(c, g, "v", P.v);
        write_rows<double>(c, g, "w", P.w);
        write_rows<double>(c, g, "f", P.f);
        write_rows<double>(c, g, "m", P.m);
        write_rows<double>(c, g, "f_ext", P.f_ext);
        write_rows<double>(c, g, "m_ext", P.m_ext);
        write_rows<double>(c, g, "x0", P.x0);
        write_rows<double>(c, g, "radius", P.radius);
        write_rows<double>(c, g, "mass", P.mass);
        write_rows<double>(c, g, "inertia", P.inertia);
        write_rows<std::uint8_t>(c, g, "fixity", P.fixity);
        write_rows<int>(c, g, "group", P.group);
        write_rows<std::int64_t>(c, g, "id", P.id);
      }
      // --- walls
      {
        const auto &W = m.walls;
        Handle      g = make_group(c, file, "walls");
        write_rows<double>(c, g, "vertex", W.vertex);
        write_rows<double>(c, g, "vertex_velocity", W.vertex_velocity);
        write_rows<double>(c, g, "vertex_force", W.vertex_force);
        write_rows<int>(c, g, "facet", W.facet);
        write_rows<int>(c, g, "facet_wall", W.facet_wall);
        write_strings(c, g, "wall_name", W.wall_name);
      }
      // --- contact groups
      {
        Handle gs = make_group(c, file, "groups");
        write_scalar<int>(c, gs, "count", m.n_groups());
        for (int gi = 0; gi < m.n_groups(); ++gi)
          {
            const ContactGroupBase<dim> &G  = m.group(gi);
            Handle                       g  = make_group(c, gs, std::to_string(gi));
            const ParamsRecord           pr = params_record(G, gi, c);
            write_strings(c, g, "law", {G.law_name()});
            write_rows<std::uint8_t>(c, g, "params_bytes", pr.bytes);
            write_strings(c, g, "params_names", pr.names);
            write_rows<double>(c, g, "params_values", pr.values);
            write_scalar<int>(c, g, "stride", G.stride());
            write_rows<std::uint32_t>(c, g, "end1", G.end1);
            write_rows<std::uint32_t>(c, g, "end2", G.end2);
            write_rows<char>(c, g, "is_wall", G.is_wall);
            write_rows<double>(c, g, "s_axis", G.s_axis);
            write_rows<double>(c, g, "n_prev", G.n_prev);
            write_rows<double>(c, g, "xc", G.xc);
            write_rows<double>(c, g, "gap", G.gap);
            write_rows<double>(c, g, "local_force", G.local_force);
            write_rows<double>(c, g, "force", G.force);
            write_rows<double>(c, g, "moment", G.moment);
            write_rows<double>(c, g, "facet_weights", G.facet_weights);
            write_data<double>(c, g, "state", G.state_data().data(), G.size(),
                               static_cast<std::size_t>(G.stride()));
            // The property blocks as doubles (their named fields listed for
            // readers; derived fields follow the named ones).
            const std::vector<double> props = G.props_data();
            write_data<double>(c, g, "props", props.data(), G.size(),
                               static_cast<std::size_t>(G.props_stride()));
            write_strings(c, g, "props_names", G.property_names());
          }
      }
      // --- cracks
      {
        Handle      g      = make_group(c, file, "cracks");
        const auto &C      = m.cracks;
        auto        column = [&](const std::string &name, auto get) {
          using T = std::decay_t<decltype(get(C[0]))>;
          std::vector<T> v;
          for (const auto &r : C)
            v.push_back(get(r));
          if constexpr (std::is_same_v<T, Vec<dim>>)
            write_rows<double>(c, g, name, v);
          else
            write_rows<T>(c, g, name, v);
        };
        column("id1", [](const Cr &r) { return r.id1; });
        column("id2", [](const Cr &r) { return r.id2; });
        column("element", [](const Cr &r) { return r.element; });
        column("mode", [](const Cr &r) { return r.mode; });
        column("type", [](const Cr &r) { return static_cast<int>(r.type); });
        column("position", [](const Cr &r) { return r.position; });
        column("normal", [](const Cr &r) { return r.normal; });
        column("size", [](const Cr &r) { return r.size; });
        column("gap", [](const Cr &r) { return r.gap; });
        column("strength", [](const Cr &r) { return r.strength; });
        column("step", [](const Cr &r) { return r.step; });
        column("time", [](const Cr &r) { return r.time; });
        column("offset", [](const Cr &r) { return r.offset; });
        column("gap_break", [](const Cr &r) { return r.gap_break; });
        column("contact_gap_break", [](const Cr &r) { return r.contact_gap_break; });
      }
    }

    /// Per-contact data of one group, read before anything is changed.
    struct GroupData
    {
      std::vector<std::uint32_t>           end1, end2;
      std::vector<char>                    is_wall;
      std::vector<Vec<dim>>                s_axis, n_prev, xc, force;
      std::vector<double>                  gap, state, props;
      std::vector<ContactForce>            local_force;
      std::vector<RotVec<dim>>             moment;
      std::vector<std::array<double, dim>> facet_weights;
    };

    static void check_params(const Model<dim> &m, hid_t gs, const Ctx &c)
    {
      const int count = read_scalar<int>(c, gs, "count");
      if (count != m.n_groups())
        throw InputError("restart: the model has " + std::to_string(m.n_groups()) +
                         " contact groups, the checkpoint " + c.file + " has " +
                         std::to_string(count));
      for (int gi = 0; gi < count; ++gi)
        {
          Handle                         g   = open_group(c, gs, std::to_string(gi));
          const std::vector<std::string> law = read_strings(c, g, "law");
          const auto                    &G   = m.group(gi);
          const std::string head = "restart: contact group " + std::to_string(gi);
          if (law.size() != 1 || law[0] != G.law_name())
            throw InputError(head + " has law '" + G.law_name() + "' here but '" +
                             (law.empty() ? "" : law[0]) + "' in the checkpoint " +
                             c.file);
          const ParamsRecord        now = params_record(G, gi, c);
          std::vector<std::uint8_t> bytes;
          std::vector<double>       values;
          read_rows<std::uint8_t>(c, g, "params_bytes", bytes, now.bytes.size());
          const auto names = read_strings(c, g, "params_names");
          read_rows<double>(c, g, "params_values", values, names.size());
          const std::string diff = "restart: parameters of contact group " +
                                   std::to_string(gi) + " (" + G.law_name() +
                                   ") differ from the checkpoint " + c.file;
          if (names != now.names)
            throw InputError(diff +
                             ": the parameter lists differ (another program version?)");
          for (std::size_t k = 0; k < names.size(); ++k)
            if (std::memcmp(&values[k], &now.values[k], sizeof(double)) != 0)
              throw InputError(diff + ": " + names[k] + " is " + fmt(now.values[k]) +
                               " here, " + fmt(values[k]) + " in the checkpoint");
          if (read_scalar<int>(c, g, "stride") != G.stride())
            throw InputError(diff + ": law state size differs");
        }
    }

    static void read(Model<dim> &m, hid_t file, const Ctx &c)
    {
      const int d = read_scalar<int>(c, file, "dim");
      if (d != dim)
        c.fail("written by a " + std::to_string(d) + "D model, cannot restart a " +
               std::to_string(dim) + "D one");
      Handle gs = open_group(c, file, "groups");
      check_params(m, gs, c);

      // Everything is read into temporaries first: a damaged file leaves
      // the model unchanged.
      Particles<dim> P;
      {
        Handle g = open_group(c, file, "particles");
        read_data<double>(c, g, "x", P.x, dim);
        const std::size_t n = P.x.size();
        read_rows<double>(c, g, "v", P.v, n);
        read_rows<double>(c, g, "w", P.w, n);
        read_rows<double>(c, g, "f", P.f, n);
        read_rows<double>(c, g, "m", P.m, n);
        read_rows<double>(c, g, "f_ext", P.f_ext, n);
        read_rows<double>(c, g, "m_ext", P.m_ext, n);
        read_rows<double>(c, g, "x0", P.x0, n);
        read_rows<double>(c, g, "radius", P.radius, n);
        read_rows<double>(c, g, "mass", P.mass, n);
        read_rows<double>(c, g, "inertia", P.inertia, n);
        read_rows<std::uint8_t>(c, g, "fixity", P.fixity, n);
        read_rows<int>(c, g, "group", P.group, n);
        read_rows<std::int64_t>(c, g, "id", P.id, n);
      }
      Walls<dim> W;
      {
        Handle g = open_group(c, file, "walls");
        read_data<double>(c, g, "vertex", W.vertex, dim);
        read_rows<double>(c, g, "vertex_velocity", W.vertex_velocity, W.vertex.size());
        read_rows<double>(c, g, "vertex_force", W.vertex_force, W.vertex.size());
        read_data<int>(c, g, "facet", W.facet, dim);
        read_rows<int>(c, g, "facet_wall", W.facet_wall, W.facet.size());
        W.wall_name = read_strings(c, g, "wall_name");
        for (std::size_t k = 0; k < W.facet.size(); ++k)
          {
            bool bad = W.facet_wall[k] < 0 || W.facet_wall[k] >= int(W.wall_name.size());
            for (int a = 0; a < dim; ++a)
              bad |= W.facet[k][a] < 0 || W.facet[k][a] >= int(W.vertex.size());
            if (bad)
              c.fail("wall facet " + std::to_string(k) +
                     " refers to a missing vertex or wall");
          }
      }
      std::vector<GroupData> groups(m.n_groups());
      for (int gi = 0; gi < m.n_groups(); ++gi)
        {
          Handle     g = open_group(c, gs, std::to_string(gi));
          GroupData &D = groups[gi];
          read_data<std::uint32_t>(c, g, "end1", D.end1, 1);
          const std::size_t nc = D.end1.size();
          read_rows<std::uint32_t>(c, g, "end2", D.end2, nc);
          read_rows<char>(c, g, "is_wall", D.is_wall, nc);
          read_rows<double>(c, g, "s_axis", D.s_axis, nc);
          read_rows<double>(c, g, "n_prev", D.n_prev, nc);
          read_rows<double>(c, g, "xc", D.xc, nc);
          read_rows<double>(c, g, "gap", D.gap, nc);
          read_rows<double>(c, g, "local_force", D.local_force, nc);
          read_rows<double>(c, g, "force", D.force, nc);
          read_rows<double>(c, g, "moment", D.moment, nc);
          read_rows<double>(c, g, "facet_weights", D.facet_weights, nc);
          const std::size_t stride = m.group(gi).stride();
          read_data<double>(c, g, "state", D.state, stride);
          if (D.state.size() != nc * stride)
            c.fail("law state of contact group " + std::to_string(gi) +
                   " has the wrong size");
          const std::size_t pstride = m.group(gi).props_stride();
          read_data<double>(c, g, "props", D.props, pstride);
          if (D.props.size() != nc * pstride)
            c.fail("property blocks of contact group " + std::to_string(gi) +
                   " have the wrong size");
          for (std::size_t k = 0; k < nc; ++k)
            if (D.end1[k] >= P.size() ||
                D.end2[k] >= (D.is_wall[k] ? W.facet.size() : P.size()))
              c.fail("contact " + std::to_string(k) + " of group " + std::to_string(gi) +
                     " refers to a missing particle or facet");
        }
      // Contact index, keyed as Model::install does.
      std::unordered_map<std::uint64_t, ContactRef> index;
      for (int gi = 0; gi < m.n_groups(); ++gi)
        for (std::size_t k = 0; k < groups[gi].end1.size(); ++k)
          {
            const auto &D = groups[gi];
            if (!index
                     .emplace(m.key(D.end1[k], D.end2[k], D.is_wall[k]),
                              ContactRef{gi, k})
                     .second)
              c.fail("duplicate contact between " + std::to_string(D.end1[k]) + " and " +
                     std::to_string(D.end2[k]));
          }
      std::vector<Cr> cracks;
      {
        Handle                    g = open_group(c, file, "cracks");
        std::vector<std::int64_t> id1, id2, step;
        std::vector<int>          element, mode, type;
        std::vector<Vec<dim>>     position, normal;
        std::vector<double>       size, gap, strength, time, gap_break, contact_gap_break;
        std::vector<Vec<dim>>     offset;
        read_data<std::int64_t>(c, g, "id1", id1, 1);
        const std::size_t n = id1.size();
        read_rows<std::int64_t>(c, g, "id2", id2, n);
        read_rows<int>(c, g, "element", element, n);
        read_rows<int>(c, g, "mode", mode, n);
        read_rows<int>(c, g, "type", type, n);
        read_rows<double>(c, g, "position", position, n);
        read_rows<double>(c, g, "normal", normal, n);
        read_rows<double>(c, g, "size", size, n);
        read_rows<double>(c, g, "gap", gap, n);
        read_rows<double>(c, g, "strength", strength, n);
        read_rows<std::int64_t>(c, g, "step", step, n);
        read_rows<double>(c, g, "time", time, n);
        read_rows<double>(c, g, "offset", offset, n);
        read_rows<double>(c, g, "gap_break", gap_break, n);
        read_rows<double>(c, g, "contact_gap_break", contact_gap_break, n);
        cracks.resize(n);
        for (std::size_t k = 0; k < n; ++k)
          {
            Cr &r = cracks[k];
            r.id1 = id1[k], r.id2 = id2[k], r.element = element[k], r.mode = mode[k];
            if (type[k] < -1 || type[k] >= n_bond_types)
              c.fail("crack " + std::to_string(k) + " has an unknown type");
            r.type     = static_cast<BondType>(type[k]);
            r.position = position[k], r.normal = normal[k];
            r.size = size[k], r.gap = gap[k], r.strength = strength[k];
            r.step = step[k], r.time = time[k];
            r.offset = offset[k], r.gap_break = gap_break[k];
            r.contact_gap_break = contact_gap_break[k];
          }
      }
      Handle     g            = open_group(c, file, "model");
      const auto step         = read_scalar<std::int64_t>(c, g, "step");
      const auto next_id      = read_scalar<std::int64_t>(c, g, "next_particle_id");
      const auto time         = read_scalar<double>(c, g, "time");
      const auto dt           = read_scalar<double>(c, g, "timestep");
      const bool auto_dt      = read_scalar<std::uint8_t>(c, g, "auto_timestep");
      const bool need_rebuild = read_scalar<std::uint8_t>(c, g, "need_rebuild");
      const int  dball        = read_scalar<int>(c, g, "default_ball_group");
      const int  dwall        = read_scalar<int>(c, g, "default_wall_group");
      if (dball >= m.n_groups() || dwall >= m.n_groups())
        c.fail("default contact-law group out of range");
      const auto          damping  = read_scalar<double>(c, g, "local_damping");
      const auto          skin     = read_scalar<double>(c, g, "skin");
      const auto          safety   = read_scalar<double>(c, g, "safety_factor");
      const bool          check_dt = read_scalar<std::uint8_t>(c, g, "check_timestep");
      std::vector<double> grav;
      read_rows<double>(c, g, "gravity", grav, dim);
      std::vector<Vec<dim>> x_rebuild, wall_rebuild;
      read_data<double>(c, g, "x_at_rebuild", x_rebuild, dim);
      read_data<double>(c, g, "wall_at_rebuild", wall_rebuild, dim);
      const auto last_ke  = read_scalar<double>(c, g, "last_kinetic_energy");
      const int  growth   = read_scalar<int>(c, g, "growth_steps");
      const bool baseline = read_scalar<std::uint8_t>(c, g, "baseline_valid");
      const auto energy0  = read_scalar<double>(c, g, "energy0");
      const auto work_in  = read_scalar<double>(c, g, "work_in");

      // ---- commit (nothing below throws) -------------------------------
      // The particle vectors are assigned one by one: the container keeps
      // its own id counter (the model was rebuilt with the same particles).
      auto &Q = m.particles;
      Q.x = std::move(P.x), Q.v = std::move(P.v), Q.w = std::move(P.w);
      Q.f = std::move(P.f), Q.m = std::move(P.m), Q.f_ext = std::move(P.f_ext);
      Q.m_ext = std::move(P.m_ext), Q.x0 = std::move(P.x0),
      Q.radius = std::move(P.radius);
      Q.mass = std::move(P.mass), Q.inertia = std::move(P.inertia);
      Q.fixity = std::move(P.fixity), Q.group = std::move(P.group),
      Q.id    = std::move(P.id);
      m.walls = std::move(W);
      for (int gi = 0; gi < m.n_groups(); ++gi)
        {
          auto &G = m.group(gi);
          auto &D = groups[gi];
          G.end1 = std::move(D.end1), G.end2 = std::move(D.end2),
          G.is_wall = std::move(D.is_wall);
          G.s_axis = std::move(D.s_axis), G.n_prev = std::move(D.n_prev),
          G.xc  = std::move(D.xc);
          G.gap = std::move(D.gap), G.local_force = std::move(D.local_force);
          G.force = std::move(D.force), G.moment = std::move(D.moment);
          G.facet_weights = std::move(D.facet_weights);
          G.state_data()  = std::move(D.state);
          G.set_props_data(D.props);
          G.topology_changed();
        }
      m.index_ = std::move(index);
      m.cracks = std::move(cracks);
      m.step_  = step;
      m.particles.set_next_particle_id(next_id);
      m.time_          = time;
      m.dt_            = dt;
      m.auto_dt_       = auto_dt;
      m.need_rebuild_  = need_rebuild;
      m.default_ball_  = dball;
      m.default_wall_  = dwall;
      m.local_damping  = damping;
      m.skin           = skin;
      m.safety_factor  = safety;
      m.check_timestep = check_dt;
      for (int a = 0; a < dim; ++a)
        m.gravity[a] = grav[a];
      m.x_at_rebuild_     = std::move(x_rebuild);
      m.wall_at_rebuild_  = std::move(wall_rebuild);
      m.ke_growth_.last   = last_ke;
      m.ke_growth_.streak = growth;
      m.baseline_valid_   = baseline;
      m.energy0_          = energy0;
      m.work_in_          = work_in;
    }
  };

  namespace
  {
    void write_metadata(const Ctx &c, hid_t file,
                        const std::map<std::string, std::string> &md)
    {
      write_strings(c, file, "format", {format_name});
      write_scalar<int>(c, file, "version", format_version);
      Handle                   g = make_group(c, file, "metadata");
      std::vector<std::string> keys, values;
      for (const auto &[k, v] : md)
        keys.push_back(k), values.push_back(v);
      write_strings(c, g, "keys", keys);
      write_strings(c, g, "values", values);
    }

    /// `checksum`: what compare_checksum said of the file (open_for_reading).
    std::map<std::string, std::string> read_metadata(const Ctx &c, hid_t file, int *dim,
                                                     int checksum)
    {
      const auto format = read_strings(c, file, "format");
      if (format.size() != 1 || format[0] != format_name)
        c.fail("not a demfem DEM checkpoint");
      const int version = read_scalar<int>(c, file, "version");
      if (version != format_version)
        c.fail("format version " + std::to_string(version) +
               " is not supported (expected " + std::to_string(format_version) + ")");
      // A current file without its checksum trailer: the trailer itself is
      // damaged (or the file was cut).
      if (checksum < 0)
        c.fail("its checksum trailer is missing or damaged: the file is damaged (use the "
               "previous checkpoint, checkpoint.h5.prev, or start again)");
      if (dim)
        *dim = read_scalar<int>(c, file, "dim");
      Handle     g      = open_group(c, file, "metadata");
      const auto keys   = read_strings(c, g, "keys");
      const auto values = read_strings(c, g, "values");
      if (keys.size() != values.size())
        c.fail("metadata keys and values differ in number");
      std::map<std::string, std::string> md;
      for (std::size_t k = 0; k < keys.size(); ++k)
        md[keys[k]] = values[k];
      return md;
    }

    void write_state(const Ctx &c, hid_t file, const NamedArrays &state)
    {
      Handle                   g = make_group(c, file, "state");
      std::vector<std::string> names;
      for (const auto &[name, values] : state)
        {
          if (name.empty() || name.find('/') != std::string::npos)
            c.fail("state entry name '" + name + "' is empty or has a '/'");
          names.push_back(name);
          write_data<double>(c, g, name, values.data(), values.size(), 1);
        }
      write_strings(c, g, "names", names);
    }

    NamedArrays read_state(const Ctx &c, hid_t file)
    {
      Handle      g = open_group(c, file, "state");
      NamedArrays state;
      for (const auto &name : read_strings(c, g, "names"))
        read_data<double>(c, g, name, state[name], 1);
      return state;
    }

    /// Reads every dataset once: InputError naming the first whose
    /// Fletcher32 checksum fails; a structure too damaged to walk is an
    /// error too when `walk_errors`.
    void verify_datasets(const Ctx &c, hid_t file, bool walk_errors = true)
    {
      struct Visit
      {
        const Ctx  *c;
        std::string failure;
      } visit{&c, ""};
      const auto each = [](hid_t loc, const char *name, const H5O_info_t *info,
                           void *data) -> herr_t {
        auto &v = *static_cast<Visit *>(data);
        if (info->type != H5O_TYPE_DATASET)
          return 0;
        try
          {
            Handle set(H5Dopen2(loc, name, H5P_DEFAULT), H5Dclose);
            if (!set.valid())
              v.c->fail(std::string("cannot open dataset '/") + name + "'");
            Handle       type(H5Dget_type(set), H5Tclose);
            Handle       space(H5Dget_space(set), H5Sclose);
            const auto   n    = H5Sget_simple_extent_npoints(space);
            const size_t size = H5Tget_size(type);
            if (H5Tis_variable_str(type) > 0 || n <= 0)
              return 0;
            std::vector<unsigned char> bytes(std::size_t(n) * size);
            read_checked(*v.c, set, type, name, bytes.data());
          }
        catch (const std::exception &e)
          {
            v.failure = e.what();
            return -1;
          }
        return 0;
      };
      const herr_t r = H5Ovisit(file, H5_INDEX_NAME, H5_ITER_NATIVE, each, &visit);
      if (!visit.failure.empty())
        throw InputError(visit.failure);
      if (r < 0 && walk_errors)
        c.fail("cannot walk its datasets (damaged file?)");
    }

    /// Opens the file after comparing it with its checksum trailer (the
    /// result in `*checksum`, for read_metadata's version-dependent check).
    Handle open_for_reading(const Ctx &c, int *checksum_state)
    {
      struct stat st;
      if (::stat(c.file.c_str(), &st) != 0)
        c.fail(std::string("cannot open: ") + std::strerror(errno));
      const int checksum = compare_checksum(c);
      *checksum_state    = checksum;
      Handle f(H5Fopen(c.file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
      if (checksum == 0)
        {
          // Damaged: name the dataset if the damage lies in one.
          if (f.valid())
            verify_datasets(c, f, false);
          c.fail("its checksum does not match its contents: the file is damaged (use the "
                 "previous checkpoint, checkpoint.h5.prev, or start again)");
        }
      if (!f.valid())
        c.fail("not an HDF5 file or damaged");
      return f;
    }
    // Debian's HDF5 is built without its thread-safety option, and the
    // packings of a calibration run on separate threads
    // (apps/parallel_packings.h): one checkpoint call at a time. Recursive:
    // an entry point may call another.
    std::recursive_mutex &hdf5_mutex()
    {
      static std::recursive_mutex m;
      return m;
    }
  } // namespace

  template <int dim>
  void write_checkpoint(const Model<dim> &model, const std::string &path,
                        const std::map<std::string, std::string> &metadata,
                        const NamedArrays                        &state)
  {
    const std::lock_guard<std::recursive_mutex> lock(hdf5_mutex());
    write_atomically(path, [&](hid_t file, const Ctx &c) {
      write_metadata(c, file, metadata);
      write_state(c, file, state);
      ModelCheckpoint<dim>::write(model, file, c);
    });
  }

  template <int dim>
  void read_checkpoint(Model<dim> &model, const std::string &path,
                       std::map<std::string, std::string> *metadata, NamedArrays *state)
  {
    const std::lock_guard<std::recursive_mutex> lock(hdf5_mutex());
    QuietHdf5                                   quiet;
    const Ctx                                   c{path, true};
    int                                         checksum = 0;
    Handle                                      file     = open_for_reading(c, &checksum);
    auto md    = read_metadata(c, file, nullptr, checksum);
    auto named = read_state(c, file);
    ModelCheckpoint<dim>::read(model, file, c);
    if (metadata)
      *metadata = std::move(md);
    if (state)
      *state = std::move(named);
  }

  void verify_checkpoint(const std::string &path)
  {
    const std::lock_guard<std::recursive_mutex> lock(hdf5_mutex());
    QuietHdf5                                   quiet;
    const Ctx                                   c{path, true};
    int                                         checksum = 0;
    Handle                                      file     = open_for_reading(c, &checksum);
    read_metadata(c, file, nullptr, checksum); // the format and version first
    verify_datasets(c, file);
  }

  std::map<std::string, std::string> read_checkpoint_metadata(const std::string &path,
                                                              int               *dim)
  {
    const std::lock_guard<std::recursive_mutex> lock(hdf5_mutex());
    QuietHdf5                                   quiet;
    const Ctx                                   c{path, true};
    int                                         checksum = 0;
    Handle                                      file     = open_for_reading(c, &checksum);
    return read_metadata(c, file, dim, checksum);
  }

  template void write_checkpoint<2>(const Model<2> &, const std::string &,
                                    const std::map<std::string, std::string> &,
                                    const NamedArrays &);
  template void write_checkpoint<3>(const Model<3> &, const std::string &,
                                    const std::map<std::string, std::string> &,
                                    const NamedArrays &);
  template void read_checkpoint<2>(Model<2> &, const std::string &,
                                   std::map<std::string, std::string> *, NamedArrays *);
  template void read_checkpoint<3>(Model<3> &, const std::string &,
                                   std::map<std::string, std::string> *, NamedArrays *);
} // namespace demfem::dem
