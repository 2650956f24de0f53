// fit.csv of `demfem calibrate --fit`: its columns, and an earlier fit's
// rows read back for Fit/resume from (apps/calibrate_fit.h; docs/
// calibrate.md, "Resuming a fit"). A 3D fit takes hours; the search is
// deterministic (NLopt's local derivative-free algorithms draw no random
// numbers, and a measurement is a deterministic function of the parameters,
// docs/calibrate.md), so replaying the logged measurements in order takes
// the optimizer along the same path to where the earlier run stopped.
#include "apps/calibrate_fit.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace demfem::apps
{
  std::string fit_csv_name(std::string n)
  {
    for (auto &c : n)
      if (c == ' ' || c == '/')
        c = '_';
    return n;
  }

  // A logged number (the log writes 17 significant digits, so a double
  // comes back bit for bit).
  double fit_log_number(const std::string &cell, const std::string &where)
  {
    std::size_t used = 0;
    double      v    = 0;
    try
      {
        v = std::stod(cell, &used);
      }
    catch (const std::exception &)
      {
        used = 0;
      }
    if (used == 0 || used != cell.size())
      throw std::invalid_argument(where + ": '" + cell + "' is not a number");
    return v;
  }

  std::vector<std::string> fit_log_cells(const std::string &line)
  {
    std::vector<std::string> c;
    std::stringstream        s(line);
    for (std::string cell; std::getline(s, cell, ',');)
      c.push_back(cell);
    if (!line.empty() && line.back() == ',')
      c.push_back(""); // an empty last cell
    return c;
  }

  std::string fit_csv_header(const FitSettings &f)
  {
    std::ostringstream h;
    h << "evaluation,stage";
    for (const auto &p : f.parameters)
      h << ',' << fit_csv_name(p.name);
    for (const auto &t : f.targets)
      h << ',' << fit_csv_name(t.name) << "_mean," << fit_csv_name(t.name) << "_sd";
    h << ",objective,all_within_tolerance,seconds,error,note\n";
    return h.str();
  }

  std::vector<FitLogRow> read_fit_log(const std::string &file, const FitSettings &f,
                                      const std::string &key)
  {
    const std::string what = key + " = " + file;
    std::ifstream     in(file);
    if (!in)
      throw std::invalid_argument(what + ": cannot be read (give the fit.csv of an "
                                         "earlier --fit run)");
    std::string header;
    std::getline(in, header);
    std::string expected = fit_csv_header(f);
    expected.pop_back(); // the newline
    if (header != expected)
      throw std::invalid_argument(what + ": its columns '" + header +
                                  "' are not this fit's '" + expected +
                                  "' (resume a fit with the same Fit/parameters and "
                                  "Fit/Targets)");
    const std::size_t      P = f.parameters.size(), T = f.targets.size();
    const std::size_t      cells = 2 + P + 2 * T + 5;
    std::vector<FitLogRow> rows;
    std::size_t            line_no = 1;
    for (std::string line; std::getline(in, line);)
      {
        ++line_no;
        if (line.empty())
          continue;
        const std::string              at = what + ", line " + std::to_string(line_no);
        const std::vector<std::string> c  = fit_log_cells(line);
        if (c.size() != cells)
          throw std::invalid_argument(at + ": " + std::to_string(c.size()) +
                                      " cells, expected " + std::to_string(cells) +
                                      " (a damaged log?)");
        FitLogRow r;
        r.stage = c[1];
        for (std::size_t i = 0; i < P; ++i)
          r.values.push_back(fit_log_number(c[2 + i], at));
        for (std::size_t i = 0; i < T; ++i)
          {
            const auto &name = f.targets[i].name;
            if (!c[2 + P + 2 * i].empty())
              r.measured.mean[name] = fit_log_number(c[2 + P + 2 * i], at);
            if (!c[3 + P + 2 * i].empty())
              r.measured.sd[name] = fit_log_number(c[3 + P + 2 * i], at);
          }
        r.seconds        = fit_log_number(c[2 + P + 2 * T + 2], at);
        r.measured.error = c[2 + P + 2 * T + 3];
        r.measured.note  = c[2 + P + 2 * T + 4];
        // A row replayed before carries that mark; the measurement's own
        // note is what follows it.
        for (const std::string mark : {"replayed; ", "replayed"})
          if (r.measured.note.rfind(mark, 0) == 0)
            {
              r.measured.note.erase(0, mark.size());
              break;
            }
        rows.push_back(r);
      }
    return rows;
  }
} // namespace demfem::apps
