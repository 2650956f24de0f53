#pragma once
// JSON numbers for every output file (docs/architecture.md, "Conventions"):
// all JSON goes through nlohmann-json; a non-finite value (a quantity that
// was not measured) is written as null, never as a bare nan or inf.
#include <nlohmann/json.hpp>

#include <cmath>

namespace demfem::dem
{
  inline nlohmann::ordered_json json_number(double v)
  {
    return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json();
  }
} // namespace demfem::dem
