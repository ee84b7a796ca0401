// Procedural buildings: archetype names and dispatch (the archetypes live in generate_*.cpp).
#include "floorcast/floorplans/generate.hpp"

#include "floorcast/core/types.hpp"

namespace floorcast {

const char* archetype_name(Archetype archetype) {
  switch (archetype) {
    case Archetype::kApartment: return "apartment";
    case Archetype::kOffice: return "office";
    case Archetype::kCampus: return "campus";
    case Archetype::kAngled: return "angled";
    case Archetype::kOfficeRepetitive: return "office_repetitive";
    case Archetype::kCampusRepetitive: return "campus_repetitive";
    case Archetype::kAngledRepetitive: return "angled_repetitive";
  }
  return "?";
}

std::vector<Archetype> all_archetypes() {
  return {Archetype::kApartment,        Archetype::kOffice,           Archetype::kCampus,
          Archetype::kAngled,           Archetype::kOfficeRepetitive, Archetype::kCampusRepetitive,
          Archetype::kAngledRepetitive};
}

Archetype parse_archetype(const std::string& name) {
  std::string valid;
  for (Archetype a : all_archetypes()) {
    if (name == archetype_name(a)) return a;
    valid += (valid.empty() ? "" : ", ") + std::string(archetype_name(a));
  }
  throw InputError("unknown archetype \"" + name + "\" (valid: " + valid + ")");
}

GeneratedBuilding generate_building(Archetype archetype, std::uint64_t seed) {
  switch (archetype) {
    case Archetype::kApartment: return generate_apartment(seed);
    case Archetype::kOffice: return generate_office(seed);
    case Archetype::kCampus: return generate_campus(seed);
    case Archetype::kAngled: return generate_angled(seed);
    case Archetype::kOfficeRepetitive: return generate_office(seed, OfficeParams::repetitive());
    case Archetype::kCampusRepetitive: return generate_campus(seed, CampusParams::repetitive());
    case Archetype::kAngledRepetitive: return generate_angled(seed, AngledParams::repetitive());
  }
  throw InputError("unknown archetype");
}

GeneratedBuilding generate_building(Archetype archetype, std::uint64_t seed, const ArchetypeOverrides& overrides) {
  auto campus = [&](CampusParams params) {
    if (overrides.campus_layout) params.layout = *overrides.campus_layout;
    if (overrides.campus_hall_variety) params.hall_variety.enabled = *overrides.campus_hall_variety;
    if (overrides.campus_hall_chamfers && !*overrides.campus_hall_chamfers) params.hall_variety.chamfer_probability = 0.0;
    return generate_campus(seed, params);
  };
  if (archetype == Archetype::kCampus) return campus(CampusParams{});
  if (archetype == Archetype::kCampusRepetitive) return campus(CampusParams::repetitive());
  return generate_building(archetype, seed);
}

}  // namespace floorcast
