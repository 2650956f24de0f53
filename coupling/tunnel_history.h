#pragma once
// history.csv of a tunnel run (docs/tunnel.md, "Output"): one row every
// Output/history interval steps. The text is kept in memory and written
// whole (temporary file + rename) at every frame, checkpoint and at the end:
// a kill leaves the last complete file, never a torn row. On restart the
// rows up to the checkpoint's step are taken back.
#include "coupling/tunnel_measures.h"
#include "dem/io/vtk_output.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

namespace demfem::coupling
{
  template <int dim>
  class TunnelHistory
  {
  public:
    explicit TunnelHistory(std::string file)
        : file_(std::move(file))
    {
    }

    static std::string header()
    {
      return std::string(
                 "step,time,phase,load_factor,unbalanced_ratio,dem_kinetic_energy,"
                 "dem_strain_energy,continuum_kinetic_energy,cracks,cracks_tensile,"
                 "cracks_shear,interface_force_imbalance,wall_convergence_mean,"
                 "ring_force_x,ring_force_y,interface_residual") +
             (dim == 3 ? ",ring_force_z" : "") + ",damage_zone_depth\n";
    }

    /// A new history: the header only.
    void start()
    {
      text_.str("");
      text_ << header();
    }

    /// One row of the model's state in `phase`.
    void record(const CoupledModel<dim> &m, const std::string &phase,
                const TunnelMeasures<dim> &measures)
    {
      const auto &D = m.dem;
      const auto  F = m.interface_force();
      text_ << D.step_count() << "," << num(D.time()) << "," << phase << ","
            << num(m.get_load_factor()) << "," << num(D.unbalanced_ratio()) << ","
            << num(D.kinetic_energy()) << "," << num(D.strain_energy()) << ","
            << num(m.continuum_kinetic_energy()) << "," << measures.cracks(-1) << ","
            << measures.cracks(0) << "," << measures.cracks(1) << ","
            << num(m.imbalance_last()) << "," << num(measures.convergence()) << ","
            << num(F[0]) << "," << num(F[1]) << "," << num(m.interface_residual());
      if constexpr (dim == 3)
        text_ << "," << num(F[dim - 1]);
      // The damage zone as it grows, stage by stage (excavation cracks).
      text_ << "," << num(measures.damage_zone_depth()) << "\n";
    }

    void save() const { dem::vtkout::write_text_atomically(file_, text_.str()); }

    /// Restart: the rows up to `step` (our own rows start "step,"), from this
    /// run's file when it continues the run in the same directory, else from
    /// `fallback` (the history next to the checkpoint: a restart into a new
    /// directory gets the whole history); then saved.
    void restore(const std::filesystem::path &fallback, std::int64_t step)
    {
      std::filesystem::path source(file_);
      if (!std::filesystem::exists(source))
        source = fallback;
      std::ifstream in(source);
      std::string   l;
      start();
      for (bool first = true; std::getline(in, l); first = false)
        {
          if (first && l + "\n" == header())
            continue;
          const auto comma    = l.find(',');
          char      *end      = nullptr;
          const auto row_step = std::strtoll(l.c_str(), &end, 10);
          if (comma != std::string::npos && end == l.c_str() + comma && row_step <= step)
            text_ << l << "\n";
        }
      save();
    }

  private:
    /// A number as the history writes it (10 digits; "null" if not finite).
    static std::string num(double x)
    {
      if (!std::isfinite(x))
        return "null";
      std::ostringstream s;
      s << std::setprecision(10) << x;
      return s.str();
    }

    std::string        file_;
    std::ostringstream text_;
  };
} // namespace demfem::coupling
