#pragma once
// JSON numbers for every output file of every layer (docs/architecture.md,
// "Conventions"): all JSON goes through nlohmann-json; a non-finite value (a quantity
// that was not measured) is written as null, never as a bare nan or inf.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>

namespace demfem
{
  /// Integral values (counts, seeds, codes) are written as integers, as a
  /// reader of an integer key expects them; others with the round-trip
  /// precision of a double.
  inline nlohmann::ordered_json json_number(double v)
  {
    if (!std::isfinite(v))
      return nlohmann::ordered_json();
    if (std::abs(v) < 9007199254740992.0 && v == std::trunc(v)) // 2^53
      return nlohmann::ordered_json(static_cast<std::int64_t>(v));
    return nlohmann::ordered_json(v);
  }
} // namespace demfem
