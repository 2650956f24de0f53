#pragma once
// The VTK series of a tunnel run (docs/tunnel.md, "Output"): at each frame
// the particles, bonds, cracks (.vtp) and the continuum (.vtu), one .pvd per
// series and tunnel.pvd holding all four as parts of each time step; every
// file replaced atomically. The frame list travels with checkpoints (text),
// so that a restarted run continues the series.
#include "coupling/coupled_model.h"
#include "dem/io/vtk_output.h"

#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace demfem::coupling
{
  template <int dim>
  class TunnelFrames
  {
  public:
    explicit TunnelFrames(std::string directory)
        : dir_(std::move(directory))
    {
    }

    /// Writes frame number size() of model `m` at its current time.
    void write(const CoupledModel<dim> &m)
    {
      const auto pf = name("particles", ".vtp"), bf = name("bonds", ".vtp"),
                 cf = name("cracks", ".vtp"), uf = name("continuum", ".vtu");
      // averaged_stress as continuum-equivalent stress: the grain stress
      // times the solid fraction inside the region's rim (particle_stress.h),
      // comparable with the continuum's stress_* arrays.
      const double n     = m.groups.interior_porosity;
      const double solid = n > 0 && n < 1 ? 1 - n : 1.0;
      dem::vtkout::write_particles(dir_ + "/" + pf, m.dem, solid);
      dem::vtkout::write_contacts(dir_ + "/" + bf, m.dem);
      dem::vtkout::write_cracks(dir_ + "/" + cf, m.dem.current_cracks());
      dem::vtkout::write_text_atomically(dir_ + "/" + uf, m.continuum_vtu());
      frames_.push_back({m.dem.time(), {pf, bf, cf, uf}});
      write_collections();
    }

    std::size_t size() const { return frames_.size(); }

    /// The frame list as text (one line per frame: time and the four files)
    /// for a checkpoint, and back.
    std::string to_text() const
    {
      std::ostringstream s;
      s << std::setprecision(17);
      for (const auto &f : frames_)
        s << f.first << " " << f.second[0] << " " << f.second[1] << " " << f.second[2]
          << " " << f.second[3] << "\n";
      return s.str();
    }
    void from_text(const std::string &text)
    {
      std::istringstream in(text);
      std::string        line;
      frames_.clear();
      while (std::getline(in, line))
        {
          std::istringstream       ls(line);
          double                   t;
          std::vector<std::string> f(4);
          ls >> t >> f[0] >> f[1] >> f[2] >> f[3];
          frames_.push_back({t, f});
        }
    }

  private:
    std::string name(const std::string &series, const char *ext) const
    {
      std::ostringstream s;
      s << series << "_" << std::setw(4) << std::setfill('0') << frames_.size() << ext;
      return s.str();
    }

    // One .pvd per series and a combined one (parts of a time step); paths
    // relative to the .pvd, times with 17 digits.
    void write_collections() const
    {
      const char *series[] = {"particles", "bonds", "cracks", "continuum"};
      const char *head     = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" "
                             "version=\"0.1\">\n<Collection>\n";
      const char *tail     = "</Collection>\n</VTKFile>\n";
      for (int s = 0; s < 4; ++s)
        {
          std::ostringstream x;
          x << head;
          for (const auto &f : frames_)
            x << "<DataSet timestep=\"" << std::setprecision(17) << f.first
              << "\" part=\"0\" file=\"" << f.second[s] << "\"/>\n";
          x << tail;
          dem::vtkout::write_text_atomically(dir_ + "/" + series[s] + ".pvd", x.str());
        }
      std::ostringstream x;
      x << head;
      for (const auto &f : frames_)
        for (int s = 0; s < 4; ++s)
          x << "<DataSet timestep=\"" << std::setprecision(17) << f.first << "\" part=\""
            << s << "\" file=\"" << f.second[s] << "\"/>\n";
      x << tail;
      dem::vtkout::write_text_atomically(dir_ + "/tunnel.pvd", x.str());
    }

    std::string                                              dir_;
    std::vector<std::pair<double, std::vector<std::string>>> frames_;
  };
} // namespace demfem::coupling
