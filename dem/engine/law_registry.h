#pragma once
// The one table that maps contact-law names (PFC keywords) to laws, so that
// input files can name a law and its properties. Adding a law = one entry.
#include "dem/engine/model.h"

#include <map>
#include <string>
#include <vector>

namespace demfem::dem
{
  /// Properties of a law by PFC keyword (e.g. "fj_kn" -> 2.32e12).
  using LawProperties = std::map<std::string, double>;

  struct LawInfo
  {
    std::string              name;
    std::string              summary;
    std::vector<std::string> keys; ///< accepted property keywords
  };

  /// The registered laws (same for 2D and 3D).
  const std::vector<LawInfo> &registered_laws();

  /// Adds a contact-law group named `law` with the given properties to the
  /// model and returns its group id. Unknown law names and unknown property
  /// keys are InputErrors that list what is allowed; ranges are checked by
  /// the law's validate(), naming `where` (e.g. the input file).
  template <int dim>
  int add_law_by_name(Model<dim> &model, const std::string &law, const LawProperties &props,
                      const std::string &where);
} // namespace demfem::dem
