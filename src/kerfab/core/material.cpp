#include "kerfab/core/material.h"

#include <limits>

#include "kerfab/core/errors.h"

namespace kerfab {

Material material_preset(const std::string& name) {
  if (name == "mdf") return {"mdf", 3.0, 1600, 18, 1.125};
  if (name == "mdf2") return {"mdf2", 2.0, 1600, 18, 1.125};
  if (name == "plywood") return {"plywood", 4.0, 620, 9.5, 1.5};
  if (name == "plywood3") return {"plywood3", 3.0, 620, 9.5, 1.5};
  if (name == "paper") return {"paper", 0.0, 1600, std::numeric_limits<double>::infinity(), 1.0};
  throw InvalidInput("--material: unknown '" + name + "' (mdf, mdf2, plywood, plywood3, paper)");
}

std::vector<Material> sheet_presets() {
  return {material_preset("mdf2"), material_preset("plywood3"), material_preset("mdf"),
          material_preset("plywood")};
}

double cutting_minutes(double length, int paths, const Machine& machine) {
  return (length / machine.speed + paths * machine.per_cut) / 60.0;
}

}  // namespace kerfab
