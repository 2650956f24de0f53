#include "dem/specimen/material_file.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>

namespace demfem::dem
{
  namespace
  {
    using json = nlohmann::json;

    /// j[key] as T, or InputError naming the file and the key.
    template <class T>
    T get(const json &j, const std::string &key, const std::string &where)
    {
      const auto it = j.find(key);
      if (it == j.end())
        throw InputError(where + ": key '" + key + "' is missing");
      try
        {
          return it->get<T>();
        }
      catch (const json::exception &)
        {
          throw InputError(where + ": key '" + key + "' has the wrong type (" +
                           it->dump() + ")");
        }
    }

    /// j[key] as an integer: JSON integers, or numbers with an integral
    /// value (10000.0); nlohmann's get<int> would truncate 1.5 to 1 silently.
    template <class T>
    T integer(const json &j, const std::string &key, const std::string &where)
    {
      const double v = get<double>(j, key, where);
      if (!(v == std::floor(v)) || v < double(std::numeric_limits<T>::min()) ||
          v > double(std::numeric_limits<T>::max()))
        throw InputError(where + ": key '" + key + "' = " + j.at(key).dump() +
                         " is not an integer");
      if (j.at(key).is_number_unsigned())
        return static_cast<T>(j.at(key).get<std::uint64_t>());
      if (j.at(key).is_number_integer())
        return static_cast<T>(j.at(key).get<std::int64_t>());
      return static_cast<T>(v);
    }

    /// The object j[key], or InputError naming the file and the key.
    const json &child(const json &j, const std::string &key, const std::string &where)
    {
      const auto it = j.find(key);
      if (it == j.end() || !it->is_object())
        throw InputError(where + ": object '" + key + "' is missing");
      return *it;
    }

    /// j[key] as T if present, else `fallback`.
    template <class T>
    T get_or(const json &j, const std::string &key, const std::string &where, T fallback)
    {
      return j.contains(key) ? get<T>(j, key, where) : fallback;
    }

    Distribution distribution(const json &j, const std::string &prefix,
                              const std::string &unit, const std::string &where)
    {
      return {get<double>(j, prefix + "_mean_" + unit, where),
              get_or<double>(j, prefix + "_sd_" + unit, where, 0.0),
              get_or<double>(j, prefix + "_min_" + unit, where, 0.0)};
    }
  } // namespace

  namespace
  {
    json parse_file(const std::string &path)
    {
      std::ifstream in(path);
      if (!in)
        throw InputError("material file '" + path + "' cannot be read");
      try
        {
          return json::parse(in);
        }
      catch (const json::exception &e)
        {
          throw InputError("material file '" + path + "' is not valid JSON: " + e.what());
        }
    }
  } // namespace

  double read_material_number(const std::string &path, const std::string &key,
                              bool required)
  {
    const json root = parse_file(path);
    const auto it   = root.find(key);
    if (!required && (it == root.end() || it->is_null()))
      return std::numeric_limits<double>::quiet_NaN();
    return get<double>(root, key, "material file '" + path + "'");
  }

  MaterialFile read_material_file(const std::string &path)
  {
    const json        root  = parse_file(path);
    const std::string where = "material file '" + path + "'";
    MaterialFile      f;
    f.dim = integer<int>(root, "dim", where);
    if (f.dim != 2 && f.dim != 3)
      throw InputError(where + ": key 'dim' = " + std::to_string(f.dim) +
                       " is not 2 or 3");
    const json &m = child(root, "microparameters", where);
    const auto  w = where + ", microparameters";
    auto       &p = f.material;
    p.type        = get<std::string>(m, "type", w);
    p.sizes.clear();
    const json &sizes = child(m, "size_distribution", w);
    for (int i = 0; sizes.contains("piece_" + std::to_string(i)); ++i)
      {
        const json       &q    = child(sizes, "piece_" + std::to_string(i), w);
        const std::string wq   = w + ", size_distribution/piece_" + std::to_string(i);
        const auto        kind = get<std::string>(q, "kind", wq);
        if (kind != "uniform" && kind != "gaussian")
          throw InputError(wq + ": key 'kind' = '" + kind +
                           "' is not 'uniform' or 'gaussian'");
        SizePiece s;
        s.gaussian        = kind == "gaussian";
        s.d_lo            = get<double>(q, "D_lo_m", wq);
        s.d_hi            = get<double>(q, "D_hi_m", wq);
        s.mean            = get_or<double>(q, "mean_m", wq, 0.0);
        s.sd              = get_or<double>(q, "sd_m", wq, 0.0);
        s.volume_fraction = get<double>(q, "volume_fraction", wq);
        p.sizes.push_back(s);
      }
    if (p.sizes.empty())
      throw InputError(w + ": size_distribution has no piece_0");
    p.diameter_multiplier = get<double>(m, "diameter_multiplier", w);
    p.density             = get<double>(m, "density_kg_m3", w);
    p.bulk_density        = get_or<double>(m, "bulk_density", w, 0.0) != 0;
    p.local_damping       = get<double>(m, "local_damping", w);
    p.seed                = integer<std::uint64_t>(m, "seed", w);
    p.lnm_emod            = get<double>(m, "lnm_emod_Pa", w);
    p.lnm_krat            = get<double>(m, "lnm_krat", w);
    p.lnm_fric            = get<double>(m, "lnm_fric", w);
    p.emod                = get<double>(m, "emod_Pa", w);
    p.krat                = get<double>(m, "krat", w);
    p.fric                = get<double>(m, "fric", w);
    p.igap                = get_or<double>(m, "igap_m", w, 0.0);
    if (p.type == "contactbonded")
      {
        p.cb_tens   = distribution(m, "cb_tens", "Pa", w);
        p.cb_shears = distribution(m, "cb_shears", "Pa", w);
      }
    if (p.type == "parallelbonded")
      {
        p.pb_rmul  = get<double>(m, "pb_rmul", w);
        p.pb_bemod = get<double>(m, "pb_bemod_Pa", w);
        p.pb_bkrat = get<double>(m, "pb_bkrat", w);
        p.pb_mcf   = get<double>(m, "pb_mcf", w);
        p.pb_ten   = distribution(m, "pb_ten", "Pa", w);
        p.pb_coh   = distribution(m, "pb_coh", "Pa", w);
        p.pb_fa    = get<double>(m, "pb_fa_deg", w);
      }
    if (p.type == "flatjointed")
      {
        p.fj_B         = get<double>(m, "fj_B", w);
        p.fj_G         = get<double>(m, "fj_G", w);
        p.fj_gap       = distribution(m, "fj_gap", "m", w);
        p.fj_Nr        = integer<int>(m, "fj_Nr", w);
        p.fj_Nal       = integer<int>(m, "fj_Nal", w);
        p.fj_rmul_code = integer<int>(m, "fj_rmul_code", w);
        p.fj_rmul      = get<double>(m, "fj_rmul", w);
        p.fj_ten       = distribution(m, "fj_ten", "Pa", w);
        p.fj_coh       = distribution(m, "fj_coh", "Pa", w);
        p.fj_fa        = get<double>(m, "fj_fa_deg", w);
      }
    p.packing        = get_or<std::string>(m, "packing", w, p.packing);
    p.Pm             = get<double>(m, "Pm_Pa", w);
    p.P_tol          = get_or<double>(m, "P_tol", w, p.P_tol);
    p.ratio_limit    = get_or<double>(m, "ratio_limit", w, p.ratio_limit);
    p.cloud_porosity = get_or<double>(m, "cloud_porosity", w, p.cloud_porosity);
    p.validate(where, f.dim);
    return f;
  }
} // namespace demfem::dem
