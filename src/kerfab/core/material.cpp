#include "kerfab/core/material.h"

#include <limits>

#include "kerfab/core/errors.h"

namespace kerfab {

Material material_preset(const std::string& name) {
  if (name == "mdf") return {"mdf", 3.0, 1600, 18, 1.125};
  if (name == "plywood") return {"plywood", 4.0, 620, 9.5, 1.5};
  if (name == "paper") return {"paper", 0.0, 1600, std::numeric_limits<double>::infinity(), 1.0};
  throw InvalidInput("--material: unknown '" + name + "' (mdf, plywood, paper)");
}

double cutting_minutes(double length, int paths, const Machine& machine) {
  return (length / machine.speed + paths * machine.per_cut) / 60.0;
}

}  // namespace kerfab
