#pragma once
// JSON numbers (common/json_number.h) under the engine's namespace.
#include "common/json_number.h"

namespace demfem::dem
{
  using demfem::json_number;
} // namespace demfem::dem
