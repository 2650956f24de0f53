// Reuse of the region's genesis packing within one process (genesis_cache.h;
// docs/study.md, "Packing reuse").
#include "coupling/genesis_cache.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <mutex>
#include <sstream>
#include <utility>

namespace demfem::coupling
{
  namespace
  {
    constexpr std::size_t capacity = 8;

    // The inputs dem::pack_specimen reads (dem/specimen/genesis.cc), written
    // exactly (hexadecimal floating point). Whatever is left out of this key
    // must not change the packing.
    std::string packing_key(const dem::MaterialParams &m, const dem::VesselParams &v,
                            int dim)
    {
      std::ostringstream k;
      k << std::hexfloat << dim << '|' << m.sizes.size();
      for (const auto &s : m.sizes)
        k << '|' << s.gaussian << ',' << s.d_lo << ',' << s.d_hi << ',' << s.mean << ','
          << s.sd << ',' << s.volume_fraction;
      k << '|' << m.diameter_multiplier << '|' << m.density << '|' << m.bulk_density
        << '|' << m.local_damping << '|' << m.seed << '|' << m.lnm_emod << '|'
        << m.lnm_krat << '|' << m.emod << '|' << m.packing << '|' << m.Pm << '|'
        << m.P_tol << '|' << m.ratio_limit << '|' << m.step_limit << '|'
        << m.cloud_porosity << '|' << m.fric_CA << '|' << m.v_limit << '|'
        << m.memory_limit;
      k << '|' << v.shape << '|' << v.H << '|' << v.W << '|' << v.D << '|' << v.expand
        << '|' << v.inset_l << '|' << v.inset_d << '|' << v.emod << '|' << v.segments;
      return k.str();
    }

    template <int dim>
    std::pair<double, double> overlap_ratios(const dem::Model<dim> &m)
    {
      double      sum = 0, mx = 0, rsum = 0;
      std::size_t n = 0;
      for (double r : m.particles.radius)
        rsum += r;
      const double rmean = rsum / std::max<std::size_t>(1, m.particles.size());
      for (int g = 0; g < m.n_groups(); ++g)
        {
          const auto &grp = m.group(g);
          for (std::size_t k = 0; k < grp.size(); ++k)
            if (!grp.is_wall[k] && grp.gap[k] < 0)
              {
                sum += -grp.gap[k];
                mx = std::max(mx, -grp.gap[k]);
                ++n;
              }
        }
      return {mx / rmean, n > 0 ? sum / n / rmean : 0.0};
    }

    template <int dim>
    struct Cache
    {
      std::mutex                                                                mutex;
      std::deque<std::pair<std::string, std::shared_ptr<const PackedBox<dim>>>> boxes;
    };
    template <int dim>
    Cache<dim> &cache()
    {
      static Cache<dim> c;
      return c;
    }
  } // namespace

  template <int dim>
  std::shared_ptr<const PackedBox<dim>> packed_box(const dem::MaterialParams &mat,
                                                   const dem::VesselParams   &v,
                                                   std::ostream              *progress,
                                                   const std::string &where, bool &reused)
  {
    // Validated on every call: a run reusing a box must still be refused
    // for its own bad keys (the box's key leaves most of them out).
    mat.validate(where, dim);
    const std::string key = packing_key(mat, v, dim);
    auto             &c   = cache<dim>();
    {
      std::lock_guard<std::mutex> lock(c.mutex);
      for (const auto &[k, box] : c.boxes)
        if (k == key)
          {
            reused = true;
            if (progress)
              *progress << where
                        << ": the packing of an earlier run in this process is reused ("
                        << box->x.size() << " grains, " << box->steps
                        << " genesis steps, " << box->wall_time_s << " s)\n";
            return box;
          }
    }
    reused         = false;
    const auto t0  = std::chrono::steady_clock::now();
    auto       box = std::make_shared<PackedBox<dim>>();
    box->rng       = dem::Random(mat.seed);
    const auto  sp = dem::pack_specimen<dim>(mat, v, box->rng, progress, where);
    const auto &Q  = sp.model.particles;
    box->x         = Q.x;
    box->radius    = Q.radius;
    box->mass      = Q.mass;
    std::tie(box->max_overlap_ratio, box->mean_overlap_ratio) = overlap_ratios(sp.model);
    box->porosity                                             = sp.porosity();
    box->steps                                                = sp.packing_steps;
    box->wall_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::lock_guard<std::mutex> lock(c.mutex);
    c.boxes.emplace_back(key, box);
    if (c.boxes.size() > capacity)
      c.boxes.pop_front();
    return box;
  }

  void clear_packed_boxes()
  {
    {
      std::lock_guard<std::mutex> lock(cache<2>().mutex);
      cache<2>().boxes.clear();
    }
    std::lock_guard<std::mutex> lock(cache<3>().mutex);
    cache<3>().boxes.clear();
  }

  template std::shared_ptr<const PackedBox<2>> packed_box<2>(const dem::MaterialParams &,
                                                             const dem::VesselParams &,
                                                             std::ostream *,
                                                             const std::string &, bool &);
  template std::shared_ptr<const PackedBox<3>> packed_box<3>(const dem::MaterialParams &,
                                                             const dem::VesselParams &,
                                                             std::ostream *,
                                                             const std::string &, bool &);
} // namespace demfem::coupling
