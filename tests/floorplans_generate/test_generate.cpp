// Procedural buildings: determinism, sizes, required features, validity, connectivity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <set>
#include <vector>
#include <string>

#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/geometry.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/raster.hpp"
#include "floorcast/floorplans/rooms.hpp"
#include "floorcast/floorplans/stats.hpp"
#include "floorcast/core/math.hpp"
#include "generate_checks.hpp"

namespace floorcast {
namespace {


const std::vector<Archetype>& archetypes() {
  static const std::vector<Archetype> a = all_archetypes();
  return a;
}

/// Generation is cheap; keep one copy per (archetype, seed) for the whole test binary.
const GeneratedBuilding& building(Archetype a, std::uint64_t seed) {
  static std::map<std::pair<int, std::uint64_t>, GeneratedBuilding> cache;
  const auto key = std::make_pair(static_cast<int>(a), seed);
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, generate_building(a, seed)).first;
  return it->second;
}

/// The shipped file of an archetype: the repetitive hard cases keep the pre-calibration names
/// (office.json, ...: the gates and baselines are measured on them), the calibrated archetypes
/// ship as NAME_calibrated.json.
std::string shipped_file(Archetype a) {
  switch (a) {
    case Archetype::kApartment: return "apartment";
    case Archetype::kOffice: return "office_calibrated";
    case Archetype::kCampus: return "campus_calibrated";
    case Archetype::kAngled: return "angled_calibrated";
    case Archetype::kOfficeRepetitive: return "office";
    case Archetype::kCampusRepetitive: return "campus";
    case Archetype::kAngledRepetitive: return "angled";
  }
  return "?";
}

std::string shipped_path(Archetype a) {
  return std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/" + shipped_file(a) + ".json";
}

TEST(Generate, ArchetypeNamesRoundTripAndUnknownNamesAreRefused) {
  for (Archetype a : archetypes()) EXPECT_EQ(parse_archetype(archetype_name(a)), a);
  try {
    parse_archetype("castle");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("castle"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("campus"), std::string::npos);
  }
}

TEST(Generate, SameSeedGivesIdenticalBytes) {
  for (Archetype a : archetypes()) {
    for (std::uint64_t seed : {0ULL, 7ULL, 123456789ULL}) {
      const std::string first = floor_plan_to_json(generate_building(a, seed).plan);
      const std::string second = floor_plan_to_json(generate_building(a, seed).plan);
      EXPECT_EQ(first, second) << archetype_name(a) << " seed " << seed;
    }
  }
}

TEST(Generate, DifferentSeedsGiveDifferentPlans) {
  for (Archetype a : archetypes()) {
    std::set<std::uint64_t> hashes;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) hashes.insert(plan_hash(building(a, seed).plan));
    EXPECT_EQ(hashes.size(), 6u) << archetype_name(a);
  }
}

TEST(Generate, ShippedBuildingsEqualAFreshGenerationWithTheirRecordedSeed) {
  const std::string readme = read_text_file(std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/README.md");
  for (Archetype a : archetypes()) {
    const std::string path = shipped_path(a);
    const std::string text = read_text_file(path);
    const FloorPlan shipped = parse_floor_plan_json(text, path);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(shipped.name, m, std::regex("\\(seed ([0-9]+)\\)"))) << shipped.name;
    const std::uint64_t seed = std::stoull(m[1].str());
    EXPECT_EQ(text, floor_plan_to_json(generate_building(a, seed).plan))
        << path << " differs from `floorcast plan generate --archetype " << archetype_name(a) << " --seed " << seed
        << "`; regenerate it with the command in floorplans/README.md";
    // The README records the command that regenerates the file.
    const std::string command = std::string("--archetype ") + archetype_name(a) + " --seed " + std::to_string(seed) +
                                " -o floorplans/buildings/" + shipped_file(a) + ".json";
    EXPECT_NE(readme.find(command), std::string::npos) << "floorplans/README.md lacks: " << command;
  }
}

TEST(Generate, PlansAreValidAndRoomsAreWellFormed) {
  for (Archetype a : archetypes()) {
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const GeneratedBuilding& b = building(a, seed);
      SCOPED_TRACE(std::string(archetype_name(a)) + " seed " + std::to_string(seed));
      EXPECT_NO_THROW(validate_floor_plan(b.plan, "generated"));
      // Round trip through the file format.
      const std::string json = floor_plan_to_json(b.plan);
      EXPECT_EQ(floor_plan_to_json(parse_floor_plan_json(json, "roundtrip")), json);
      std::set<std::string> ids;
      for (const GeneratedRoom& r : b.rooms) {
        EXPECT_TRUE(ids.insert(r.id).second) << "duplicate room id " << r.id;
        EXPECT_GT(test::polygon_area(r.polygon_m), 1.0) << r.id;  // counter-clockwise, not a sliver
      }
    }
  }
}

TEST(Generate, RoomsDoNotOverlap) {
  for (Archetype a : archetypes()) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const GeneratedBuilding& b = building(a, seed);
      SCOPED_TRACE(std::string(archetype_name(a)) + " seed " + std::to_string(seed));
      std::vector<Eigen::Vector4d> boxes;
      for (const GeneratedRoom& r : b.rooms) {
        Eigen::Vector4d box(1e300, 1e300, -1e300, -1e300);
        for (const Vec2& p : r.polygon_m) {
          box = Eigen::Vector4d(std::min(box[0], p.x()), std::min(box[1], p.y()), std::max(box[2], p.x()),
                                std::max(box[3], p.y()));
        }
        boxes.push_back(box);
      }
      int overlaps = 0;
      for (std::size_t i = 0; i < b.rooms.size(); ++i) {
        const Eigen::Vector4d& bi = boxes[i];
        for (double x = bi[0] + 0.05; x < bi[2]; x += 0.5) {
          for (double y = bi[1] + 0.05; y < bi[3]; y += 0.5) {
            const Vec2 p(x, y);
            if (!test::inside_polygon(b.rooms[i].polygon_m, p)) continue;
            for (std::size_t j = 0; j < b.rooms.size(); ++j) {
              if (j == i) continue;
              const Eigen::Vector4d& bj = boxes[j];
              if (x < bj[0] || x > bj[2] || y < bj[1] || y > bj[3]) continue;
              if (test::inside_polygon(b.rooms[j].polygon_m, p)) ++overlaps;
            }
          }
        }
      }
      EXPECT_EQ(overlaps, 0);
    }
  }
}

TEST(Generate, EnvelopeIsClosedAndEveryRoomIsReachableThroughDoors) {
  for (Archetype a : archetypes()) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const GeneratedBuilding& b = building(a, seed);
      SCOPED_TRACE(std::string(archetype_name(a)) + " seed " + std::to_string(seed));
      // Every door and window closed: no room reaches the outside (no gap bridging at all).
      const test::EnvelopeRaster env = test::envelope_raster(b.plan, 0.1);
      for (const GeneratedRoom& r : b.rooms) {
        int row, col;
        ASSERT_TRUE(env.grid.world_to_cell(test::polygon_centroid(r.polygon_m), row, col));
        EXPECT_EQ(env.outside.at<std::uint8_t>(row, col), 0) << r.id << " leaks to the outside";
      }
      // Every door open: the interior is one connected free space.
      EXPECT_EQ(test::interior_components_doors_open(b.plan, 0.1), 1);
      // With the doors as generated, closed doors really separate something.
      const auto c = plan_counts(b.plan);
      EXPECT_GT(c.doors_closed, 0);
      EXPECT_LT(c.doors_closed, c.doors);
    }
  }
}

TEST(Generate, ManySeedsGiveValidConnectedBuildings) {
  // A wider sweep than the detailed tests (which use seeds 1-6): generation must never fail and
  // every building must be one connected interior with all doors open.
  for (Archetype a : archetypes()) {
    for (std::uint64_t seed = 100; seed < 125; ++seed) {
      SCOPED_TRACE(std::string(archetype_name(a)) + " seed " + std::to_string(seed));
      BuildingStyle bare;
      bare.furniture = false;
      GeneratedBuilding b;
      switch (a) {
        case Archetype::kApartment: {
          ApartmentParams p;
          p.style.furniture = false;
          b = generate_apartment(seed, p);
          break;
        }
        case Archetype::kOfficeRepetitive: {
          OfficeParams p = OfficeParams::repetitive();
          p.style = bare;
          b = generate_office(seed, p);
          break;
        }
        case Archetype::kCampusRepetitive: {
          CampusParams p = CampusParams::repetitive();
          p.style.furniture = false;
          b = generate_campus(seed, p);
          break;
        }
        case Archetype::kAngledRepetitive: {
          AngledParams p = AngledParams::repetitive();
          p.style = bare;
          b = generate_angled(seed, p);
          break;
        }
        case Archetype::kOffice: {
          OfficeParams p;
          p.style = bare;
          b = generate_office(seed, p);
          break;
        }
        case Archetype::kCampus: {
          CampusParams p;
          p.style.furniture = false;
          b = generate_campus(seed, p);
          break;
        }
        case Archetype::kAngled: {
          AngledParams p;
          p.style = bare;
          b = generate_angled(seed, p);
          break;
        }
      }
      EXPECT_EQ(test::interior_components_doors_open(b.plan, 0.2), 1);
    }
  }
}

TEST(Generate, RealisticDimensions) {
  for (Archetype a : archetypes()) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const GeneratedBuilding& b = building(a, seed);
      SCOPED_TRACE(std::string(archetype_name(a)) + " seed " + std::to_string(seed));
      std::set<std::string> exterior_walls;
      for (const Wall& w : b.plan.walls) {
        if (w.material == WallMaterial::kGlass) {
          EXPECT_NEAR(w.thickness_m, 0.05, 1e-9) << w.id;
        } else if (w.id.rfind("ext", 0) == 0) {
          EXPECT_NEAR(w.thickness_m, 0.30, 1e-9) << w.id;
          exterior_walls.insert(w.id);
        } else {
          EXPECT_GE(w.thickness_m, 0.10 - 1e-9) << w.id;
          EXPECT_LE(w.thickness_m, 0.15 + 1e-9) << w.id;
        }
      }
      for (const Door& d : b.plan.doors) {
        const bool single = d.width_m >= 0.8 - 1e-9 && d.width_m <= 1.0 + 1e-9;
        const bool dbl = d.width_m >= 1.5 - 1e-9 && d.width_m <= 1.9 + 1e-9;
        EXPECT_TRUE(single || dbl) << d.id << " width " << d.width_m;
      }
      // Windows sit in exterior walls: one side of every window is the outside.
      const test::EnvelopeRaster env = test::envelope_raster(b.plan, 0.1);
      ASSERT_GT(b.plan.windows.size(), 0u);
      for (const Window& w : b.plan.windows) {
        EXPECT_EQ(exterior_walls.count(w.wall_id), 1u) << w.id << " in " << w.wall_id;
        const Wall& wall = b.plan.walls[static_cast<std::size_t>(b.plan.wall_index(w.wall_id))];
        const Vec2 d = wall.direction();
        const Vec2 n(-d.y(), d.x());
        int outside_sides = 0;
        for (double s : {-0.6, 0.6}) {
          int row, col;
          ASSERT_TRUE(env.grid.world_to_cell(w.center_m + s * n, row, col));
          outside_sides += env.outside.at<std::uint8_t>(row, col) ? 1 : 0;
        }
        EXPECT_EQ(outside_sides, 1) << w.id;
      }
    }
  }
}

TEST(Generate, EveryArchetypeHasClosedDoorsWindowsAndGlass) {
  for (Archetype a : archetypes()) {
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      const PlanCounts c = plan_counts(building(a, seed).plan);
      SCOPED_TRACE(std::string(archetype_name(a)) + " seed " + std::to_string(seed));
      EXPECT_GT(c.doors_closed, 0);
      EXPECT_GT(c.windows, 0);
      EXPECT_GT(c.glass_walls, 0);
    }
  }
}

TEST(Generate, FreeFloorAreasAreWithinTheArchetypeRanges) {
  const std::map<Archetype, std::pair<double, double>> ranges = {
      {Archetype::kApartment, {80.0, 150.0}},
      {Archetype::kOffice, {800.0, 2500.0}},  // calibrated: within the small real levels (180-2,200 m^2)
      {Archetype::kAngled, {900.0, 2500.0}},
      {Archetype::kCampus, {8000.0, 15000.0}},
      {Archetype::kOfficeRepetitive, {1500.0, 3000.0}},
      {Archetype::kCampusRepetitive, {8000.0, 15000.0}},
  };
  for (const auto& [a, range] : ranges) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const double area = free_floor_area_m2(building(a, seed).plan);
      EXPECT_GE(area, range.first) << archetype_name(a) << " seed " << seed;
      EXPECT_LE(area, range.second) << archetype_name(a) << " seed " << seed;
    }
  }
}

std::map<std::string, int> kind_counts(const GeneratedBuilding& b) {
  std::map<std::string, int> n;
  for (const GeneratedRoom& r : b.rooms) ++n[r.kind];
  return n;
}

/// Number of rooms of `kind` sharing the most common footprint size (rounded to 1 cm).
int largest_identical_group(const GeneratedBuilding& b, const std::string& kind) {
  std::map<std::pair<long, long>, int> sizes;
  for (const GeneratedRoom& r : b.rooms) {
    if (r.kind != kind || r.polygon_m.size() != 4) continue;
    const double e1 = (r.polygon_m[1] - r.polygon_m[0]).norm(), e2 = (r.polygon_m[2] - r.polygon_m[1]).norm();
    ++sizes[{std::lround(100.0 * std::min(e1, e2)), std::lround(100.0 * std::max(e1, e2))}];
  }
  int best = 0;
  for (const auto& [size, count] : sizes) best = std::max(best, count);
  return best;
}

/// Length of the longer side of a rectangle room.
double room_length(const GeneratedRoom& r) {
  double best = 0.0;
  for (std::size_t i = 0; i < r.polygon_m.size(); ++i) {
    best = std::max(best, (r.polygon_m[(i + 1) % r.polygon_m.size()] - r.polygon_m[i]).norm());
  }
  return best;
}

/// Pairs of hallway rooms sharing at least 1 m of boundary (hallway junctions).
int hallway_junctions(const GeneratedBuilding& b) {
  std::vector<const GeneratedRoom*> halls;
  for (const GeneratedRoom& r : b.rooms) {
    if (r.kind == "hallway") halls.push_back(&r);
  }
  int count = 0;
  for (std::size_t i = 0; i < halls.size(); ++i) {
    for (std::size_t j = i + 1; j < halls.size(); ++j) {
      double shared = 0.0;
      const auto& p = halls[i]->polygon_m;
      const auto& q = halls[j]->polygon_m;
      for (std::size_t a = 0; a < p.size(); ++a) {
        const Vec2 p0 = p[a], p1 = p[(a + 1) % p.size()];
        const Vec2 d = (p1 - p0).normalized();
        for (std::size_t c = 0; c < q.size(); ++c) {
          const Vec2 q0 = q[c], q1 = q[(c + 1) % q.size()];
          const Vec2 n(-d.y(), d.x());
          if (std::abs(n.dot(q0 - p0)) > 1e-3 || std::abs(n.dot(q1 - p0)) > 1e-3) continue;
          const double t0 = std::max(0.0, std::min(d.dot(q0 - p0), d.dot(q1 - p0)));
          const double t1 = std::min((p1 - p0).norm(), std::max(d.dot(q0 - p0), d.dot(q1 - p0)));
          shared += std::max(0.0, t1 - t0);
        }
      }
      if (shared >= 1.0) ++count;
    }
  }
  return count;
}

TEST(Generate, CampusHasLongHallwaysIntersectionsLobbyAtriumAndLectureHalls) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const GeneratedBuilding& b = building(Archetype::kCampusRepetitive, seed);
    SCOPED_TRACE("seed " + std::to_string(seed));
    int long_hallways = 0;
    for (const GeneratedRoom& r : b.rooms) {
      if (r.kind == "hallway" && room_length(r) >= 100.0) ++long_hallways;
    }
    EXPECT_GE(long_hallways, 3);
    EXPECT_GE(hallway_junctions(b), 8);
    const auto kinds = kind_counts(b);
    EXPECT_EQ(kinds.count("lobby"), 1u);
    EXPECT_EQ(kinds.count("atrium"), 1u);
    ASSERT_GE(kinds.count("lecture_hall"), 1u);
    EXPECT_GE(kinds.at("lecture_hall"), 2);
    for (const GeneratedRoom& r : b.rooms) {
      if (r.kind == "lecture_hall") {
        EXPECT_GE(test::polygon_area(r.polygon_m), 200.0) << r.id;
      }
    }
    EXPECT_GE(largest_identical_group(b, "office"), 30);
    EXPECT_GE(plan_counts(b.plan).glass_walls, 3);  // lobby facade + atrium walls
  }
}

TEST(Generate, OfficeHasDoubleLoadedCorridorsStairsAndMeetingRooms) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const GeneratedBuilding& b = building(Archetype::kOfficeRepetitive, seed);
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto kinds = kind_counts(b);
    ASSERT_GE(kinds.count("stairwell"), 1u);
    EXPECT_GE(kinds.at("stairwell"), 2);
    ASSERT_GE(kinds.count("meeting"), 1u);
    EXPECT_GE(largest_identical_group(b, "office"), 20);
    EXPECT_GE(hallway_junctions(b), 2);  // corner junction, fire partitions
  }
}

// The calibrated archetypes keep their features but lose the rows of identical rooms: on the
// structure measures they sit inside the small real levels' range (plan stats on
// ../shared/realplans: repeated room widths 0-0.75, room-area q3/q1 1.4-27), the repetitive ones
// outside it.
TEST(Generate, CalibratedArchetypesVaryTheirRoomsTheRepetitiveOnesDoNot) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    for (Archetype a : {Archetype::kOffice, Archetype::kAngled, Archetype::kCampus}) {
      const PlanStats s = plan_stats(building(a, seed).plan);
      SCOPED_TRACE(archetype_name(a));
      EXPECT_LE(s.repeated_width_share, 0.75);
      EXPECT_GE(s.room_area_m2.q3 / s.room_area_m2.q1, 1.4);
      EXPECT_GE(s.room_area_m2.cv, 0.4);
    }
    for (Archetype a : {Archetype::kOfficeRepetitive, Archetype::kAngledRepetitive}) {
      const PlanStats s = plan_stats(building(a, seed).plan);
      SCOPED_TRACE(archetype_name(a));
      EXPECT_LT(s.room_area_m2.q3 / s.room_area_m2.q1, 1.3);
      EXPECT_GE(largest_identical_group(building(a, seed), "office"), 20);
    }
    // Calibrated office: still two wings with stairwells, a conference room, junctions; recesses
    // and stubs are hallway pieces open to the corridors.
    const GeneratedBuilding& office = building(Archetype::kOffice, seed);
    const auto kinds = kind_counts(office);
    ASSERT_GE(kinds.count("stairwell"), 1u);
    EXPECT_GE(kinds.at("stairwell"), 2);
    EXPECT_GE(kinds.count("meeting"), 1u);
    EXPECT_GE(hallway_junctions(office), 4);
    EXPECT_LT(largest_identical_group(office, "office"), 8);
  }
}

// The calibrated campus is measured against the large real levels (plan stats and the room
// polygons of SPbSTU main L0-L2 and the Grenoble mall L-1..L1, results/realplans_vs_generated.md):
// transitional share of the room area 0.04-0.25, doors per 10 m of wall 0.00-0.41 (SPbSTU main,
// which maps its doors: 0.20-0.41), room-area cv 1.05-2.04, median room 17.9-169.5 m^2, median
// corridor width 4.0-5.0 m on SPbSTU main, two rooms of 570 m^2 or more and 8-11 of 200 m^2 or
// more per SPbSTU main level; 89-100% of the room area on a facade, every hall of 200 m^2 or more
// on a facade, 24-30% of the transitional boundary on a facade (one-sided corridors). Tolerances:
// the spine campus's range over seeds 1-8 (circulation 0.20-0.25, doors 0.40-0.46 per 10 m: more
// rooms per m^2 than SPbSTU main, cv 1.42-1.62, room area on a facade 0.98-1.00, transitional
// boundary on a facade 0.11-0.26: alcoves and stubs add boundary between rooms) with a margin. The blocks layout (the calibrated campus before the spine, CampusLayout::kBlocks) is
// outside on the layout measures: circulation 0.27-0.30, 43-46% of the room area on a facade,
// 0-1 of 7-8 halls, 4% of the hallway boundary.
TEST(Generate, CalibratedCampusHasTheLargeRealLevelsStructure) {
  auto rooms_at_least = [](const GeneratedBuilding& b, double area_m2) {
    int n = 0;
    for (const GeneratedRoom& r : b.rooms) {
      if (!is_transitional_kind(r.kind) && test::polygon_area(r.polygon_m) >= area_m2) ++n;
    }
    return n;
  };
  auto circulation_share = [](const GeneratedBuilding& b) {
    double all = 0.0, transitional = 0.0;
    for (const GeneratedRoom& r : b.rooms) {
      const double a = test::polygon_area(r.polygon_m);
      all += a;
      if (is_transitional_kind(r.kind)) transitional += a;
    }
    return transitional / all;
  };
  // Boundary of a room whose outside (0.6 m beyond the edge, past any wall) is in no room: facade.
  auto facade_length_m = [](const GeneratedBuilding& b, const GeneratedRoom& room, double* perimeter_m) {
    const std::vector<Vec2>& poly = room.polygon_m;  // counter-clockwise
    double facade = 0.0;
    *perimeter_m = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 a = poly[i], e = poly[(i + 1) % poly.size()] - a;
      const double len = e.norm();
      if (len < 1e-6) continue;
      const Vec2 out(e.y() / len, -e.x() / len);
      const int steps = std::max(1, static_cast<int>(len / 0.5));
      for (int k = 0; k < steps; ++k) {
        const Vec2 q = a + e * ((k + 0.5) / steps) + 0.6 * out;
        const bool in_room = std::any_of(b.rooms.begin(), b.rooms.end(), [&](const GeneratedRoom& o) {
          return &o != &room && point_in_polygon(o.polygon_m, q);
        });
        if (!in_room) facade += len / steps;
      }
      *perimeter_m += len;
    }
    return facade;
  };
  struct LayoutMeasures {
    double circulation, room_area_on_facade, transitional_boundary_on_facade;
    int halls, halls_on_facade;
  };
  auto layout_measures = [&](const GeneratedBuilding& b) {
    double room_area = 0.0, facade_area = 0.0, boundary = 0.0, boundary_facade = 0.0;
    int halls = 0, halls_on_facade = 0;
    for (const GeneratedRoom& r : b.rooms) {
      double perimeter = 0.0;
      const double facade = facade_length_m(b, r, &perimeter);
      const double a = test::polygon_area(r.polygon_m);
      if (is_transitional_kind(r.kind)) {
        boundary += perimeter;
        boundary_facade += facade;
        continue;
      }
      room_area += a;
      if (facade >= 1.0) facade_area += a;
      if (a >= 200.0) {
        ++halls;
        if (facade >= 1.0) ++halls_on_facade;
      }
    }
    return LayoutMeasures{circulation_share(b), facade_area / room_area, boundary_facade / boundary, halls, halls_on_facade};
  };
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const GeneratedBuilding& b = building(Archetype::kCampus, seed);
    const PlanStats s = plan_stats(b.plan);
    const LayoutMeasures m = layout_measures(b);
    EXPECT_GE(m.circulation, 0.04);
    EXPECT_LE(m.circulation, 0.26);
    EXPECT_GE(m.room_area_on_facade, 0.85);
    EXPECT_EQ(m.halls_on_facade, m.halls);
    EXPECT_GE(m.transitional_boundary_on_facade, 0.10);
    EXPECT_LE(m.transitional_boundary_on_facade, 0.35);
    EXPECT_LE(s.doors_per_10m_wall, 0.47);
    EXPECT_GE(s.room_area_m2.cv, 1.2);
    EXPECT_GE(s.room_area_m2.median, 17.9);
    EXPECT_LE(s.room_area_m2.median, 169.5);
    EXPECT_GE(s.corridor_width_m.median, 4.0 - 0.05);
    EXPECT_LE(s.corridor_width_m.median, 5.0 + 0.05);
    EXPECT_EQ(s.directions_used, 2);
    EXPECT_GE(rooms_at_least(b, 570.0), 2);   // the great halls
    EXPECT_GE(rooms_at_least(b, 200.0), 6);   // great halls, lecture and end halls

    // The blocks layout with the same calibration: inside on the plan-stats measures, outside on
    // the layout ones (the measures can fail).
    CampusParams blocks;
    blocks.layout = CampusLayout::kBlocks;
    const GeneratedBuilding bb = generate_campus(seed, blocks);
    const LayoutMeasures mb = layout_measures(bb);
    EXPECT_GT(mb.circulation, 0.25);
    EXPECT_LT(mb.room_area_on_facade, 0.6);
    EXPECT_LT(mb.halls_on_facade, mb.halls);
    EXPECT_LT(mb.transitional_boundary_on_facade, 0.1);
    EXPECT_LE(plan_stats(bb.plan).walls, 250);

    const GeneratedBuilding& r = building(Archetype::kCampusRepetitive, seed);
    const PlanStats sr = plan_stats(r.plan);
    EXPECT_LT(sr.room_area_m2.cv, 0.95);
    EXPECT_LT(sr.corridor_width_m.median, 3.5);
    EXPECT_EQ(rooms_at_least(r, 570.0), 0);
  }
}

// The spine layout is deterministic by seed and every seed gives a valid, connected building.
TEST(Generate, CampusSpineIsDeterministicValidAndConnected) {
  CampusParams p;
  p.style.furniture = false;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const GeneratedBuilding b = generate_campus(seed, p);
    EXPECT_EQ(floor_plan_to_json(b.plan), floor_plan_to_json(generate_campus(seed, p).plan));
    EXPECT_NO_THROW(validate_floor_plan(b.plan, "generated"));
    EXPECT_EQ(test::interior_components_doors_open(b.plan, 0.2), 1);
  }
}

// The halls (rooms of 200 m^2 or more) of the calibrated campus against SPbSTU main L0-L2's 30
// (results/realplans_vs_generated.md, "Halls"; the large real levels' halls that map doors): 15 of
// 30 not rectangles (area / minimum-area rectangle 0.68-0.96, median 0.86; 6-16 corners, 0-4
// reflex), 19 / 6 / 5 with 1 / 2 / 3 or more doors, door centres 0.09-0.50 of the side from the
// nearest corner, 20 of 48 doors within 0.02 of 1/4 or 1/2 of their side. Tolerances (pooled over
// seeds 1-8): non-rectangular share 0.3-0.7, shaped halls' rectangularity 0.60-0.99 with the
// median 0.78-0.95, at most 16 corners and 4 reflex ones, one-door share 0.45-0.80, 3 or more
// doors in at least 5% of the halls, at most 60% of the doors at 1/4 or 1/2 of their side. The
// spine campus before (HallVariety::enabled = false) is outside: every hall a rectangle, two doors
// at 1/4 and 3/4 or one at the middle (the measures can fail).
TEST(Generate, CalibratedCampusHallsHaveTheRealHallsShapesAndDoors) {
  struct HallMeasures {
    int halls = 0, shaped = 0, one_door = 0, three_doors = 0, max_corners = 0, max_reflex = 0, doors = 0,
        doors_at_quarter_or_middle = 0;
    std::vector<double> shaped_rectangularity;
  };
  auto measure = [](const std::vector<GeneratedBuilding>& buildings) {
    HallMeasures m;
    for (const GeneratedBuilding& b : buildings) {
      for (const GeneratedRoom& r : b.rooms) {
        const double area = test::polygon_area(r.polygon_m);
        if (is_transitional_kind(r.kind) || area < 200.0) continue;
        ++m.halls;
        // The campus is axis aligned: the minimum-area rectangle is the bounding box.
        double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
        for (const Vec2& q : r.polygon_m) {
          x0 = std::min(x0, q.x()), y0 = std::min(y0, q.y()), x1 = std::max(x1, q.x()), y1 = std::max(y1, q.y());
        }
        const double rectangularity = area / ((x1 - x0) * (y1 - y0));
        if (rectangularity < 0.99) {
          ++m.shaped;
          m.shaped_rectangularity.push_back(rectangularity);
        }
        const std::size_t n = r.polygon_m.size();
        int reflex = 0;
        for (std::size_t i = 0; i < n; ++i) {  // counter-clockwise: a right turn is a reflex corner
          const Vec2 e0 = r.polygon_m[i] - r.polygon_m[(i + n - 1) % n], e1 = r.polygon_m[(i + 1) % n] - r.polygon_m[i];
          if (e0.x() * e1.y() - e0.y() * e1.x() < 0.0) ++reflex;
        }
        m.max_corners = std::max(m.max_corners, static_cast<int>(n));
        m.max_reflex = std::max(m.max_reflex, reflex);
        int doors = 0;
        for (const Door& d : b.plan.doors) {
          double dist = 1e18;
          for (std::size_t i = 0; i < n; ++i) {
            dist = std::min(dist, point_segment_distance(d.center_m, Segment2{r.polygon_m[i], r.polygon_m[(i + 1) % n]}));
          }
          if (dist > 0.4) continue;
          ++doors;
          // Share of the bounding box side from its nearest corner.
          const bool on_x_side = std::abs(d.center_m.y() - y0) < 0.4 || std::abs(d.center_m.y() - y1) < 0.4;
          const double share = on_x_side ? std::min(d.center_m.x() - x0, x1 - d.center_m.x()) / (x1 - x0)
                                         : std::min(d.center_m.y() - y0, y1 - d.center_m.y()) / (y1 - y0);
          if (std::abs(share - 0.25) <= 0.02 || std::abs(share - 0.5) <= 0.02) ++m.doors_at_quarter_or_middle;
        }
        m.doors += doors;
        if (doors == 1) ++m.one_door;
        if (doors >= 3) ++m.three_doors;
        EXPECT_GE(doors, 1) << r.id;
      }
    }
    return m;
  };
  std::vector<GeneratedBuilding> varied, plain;
  CampusParams before;
  before.hall_variety.enabled = false;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    varied.push_back(generate_campus(seed));
    plain.push_back(generate_campus(seed, before));
  }
  HallMeasures m = measure(varied);
  ASSERT_GE(m.halls, 40);
  const double shaped = static_cast<double>(m.shaped) / m.halls;
  EXPECT_GE(shaped, 0.3);
  EXPECT_LE(shaped, 0.7);
  ASSERT_FALSE(m.shaped_rectangularity.empty());
  std::sort(m.shaped_rectangularity.begin(), m.shaped_rectangularity.end());
  EXPECT_GE(m.shaped_rectangularity.front(), 0.60);
  const double median = m.shaped_rectangularity[m.shaped_rectangularity.size() / 2];
  EXPECT_GE(median, 0.78);
  EXPECT_LE(median, 0.95);
  EXPECT_LE(m.max_corners, 16);
  EXPECT_LE(m.max_reflex, 4);
  const double one_door = static_cast<double>(m.one_door) / m.halls;
  EXPECT_GE(one_door, 0.45);
  EXPECT_LE(one_door, 0.80);
  EXPECT_GE(static_cast<double>(m.three_doors) / m.halls, 0.05);
  EXPECT_LE(static_cast<double>(m.doors_at_quarter_or_middle) / m.doors, 0.6);

  const HallMeasures mp = measure(plain);
  EXPECT_EQ(mp.shaped, 0);
  EXPECT_EQ(mp.three_doors, 0);
  EXPECT_GE(static_cast<double>(mp.doors_at_quarter_or_middle) / mp.doors, 0.8);
}

// A third of the campus's halls have chamfered corners, as a third of SPbSTU main's halls have sides
// oblique to the building's axes (10 of 30; 3 [2-8] per such hall, 1.5-10.3 m long;
// scripts/realplans_vs_generated.py, "Halls"). The chamfers come from a random stream of their own:
// without them the building is the same but for those halls' outlines and seat rows.
TEST(Generate, CalibratedCampusHallsHaveObliqueSidesLikeTheRealHalls) {
  CampusParams orthogonal;
  orthogonal.hall_variety.chamfer_probability = 0.0;
  int halls = 0, chamfered_halls = 0;
  std::vector<double> lengths;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const GeneratedBuilding b = generate_campus(seed), o = generate_campus(seed, orthogonal);
    ASSERT_EQ(b.rooms.size(), o.rooms.size()) << seed;
    EXPECT_EQ(b.plan.doors.size(), o.plan.doors.size()) << seed;
    for (std::size_t i = 0; i < b.rooms.size(); ++i) {
      const GeneratedRoom& r = b.rooms[i];
      const GeneratedRoom& q = o.rooms[i];
      ASSERT_EQ(r.id, q.id) << seed;
      std::vector<double> oblique;  // the campus is axis aligned: any other side is oblique
      for (std::size_t k = 0; k < r.polygon_m.size(); ++k) {
        const Vec2 d = r.polygon_m[(k + 1) % r.polygon_m.size()] - r.polygon_m[k];
        if (std::abs(d.x()) < 1e-6 || std::abs(d.y()) < 1e-6) continue;
        oblique.push_back(d.norm());
        // 45 degrees, steeper where a great hall was deepened to hold its area.
        const double deg = std::atan2(std::abs(d.y()), std::abs(d.x())) * 180.0 / kPi;
        EXPECT_GE(deg, 30.0) << r.id;
        EXPECT_LE(deg, 60.0) << r.id;
      }
      if (r.polygon_m == q.polygon_m) {
        EXPECT_TRUE(oblique.empty()) << r.id;
        continue;
      }
      EXPECT_EQ(r.kind, "lecture_hall") << seed << " " << r.id;
      EXPECT_GE(oblique.size(), 2u) << r.id;
      // The seat rows stay inside the chamfered outline.
      for (const Obstacle& ob : b.plan.obstacles) {
        if (!test::inside_polygon(q.polygon_m, ob.center_m)) continue;
        const double c = std::cos(ob.yaw_rad), sn = std::sin(ob.yaw_rad);
        for (const Vec2& uv : {Vec2(-0.5, -0.5), Vec2(0.5, -0.5), Vec2(0.5, 0.5), Vec2(-0.5, 0.5)}) {
          const Vec2 local(uv.x() * ob.size_m.x(), uv.y() * ob.size_m.y());
          const Vec2 corner = ob.center_m + Vec2(c * local.x() - sn * local.y(), sn * local.x() + c * local.y());
          EXPECT_TRUE(test::inside_polygon(r.polygon_m, corner)) << seed << " " << ob.id << " outside " << r.id;
        }
      }
      if (test::polygon_area(r.polygon_m) >= 200.0) {
        ++chamfered_halls;
        lengths.insert(lengths.end(), oblique.begin(), oblique.end());
      }
    }
    for (const GeneratedRoom& r : b.rooms) {
      if (!is_transitional_kind(r.kind) && test::polygon_area(r.polygon_m) >= 200.0) ++halls;
    }
  }
  ASSERT_GE(halls, 40);
  const double share = static_cast<double>(chamfered_halls) / halls;
  EXPECT_GE(share, 0.2);
  EXPECT_LE(share, 0.45);
  ASSERT_FALSE(lengths.empty());
  std::sort(lengths.begin(), lengths.end());
  EXPECT_GE(lengths.front(), 0.5 * std::sqrt(2.0) - 1e-6);
  EXPECT_LE(lengths.back(), 10.5);
  const double median = lengths[lengths.size() / 2];
  EXPECT_GE(median, 2.5);
  EXPECT_LE(median, 7.0);
}

// Every variety feature at its extreme (always / never) still gives valid, connected buildings.
TEST(Generate, ExtremeVarietyStillGivesValidConnectedBuildings) {
  for (double p : {0.0, 1.0}) {
    RoomVariety v;
    v.recess_probability = v.notch_probability = v.suite_probability = v.stub_probability = p;
    v.glass_wall_probability = p;
    v.irregular_cores = p > 0.5;
    for (std::uint64_t seed = 200; seed < 206; ++seed) {
      SCOPED_TRACE("p " + std::to_string(p) + " seed " + std::to_string(seed));
      OfficeParams op;
      op.style.furniture = false;
      op.variety = v;
      AngledParams ap;
      ap.style.furniture = false;
      ap.variety = v;
      CampusParams cp;
      cp.style.furniture = false;
      cp.variety = v;
      for (const GeneratedBuilding& b : {generate_office(seed, op), generate_angled(seed, ap), generate_campus(seed, cp)}) {
        SCOPED_TRACE(b.plan.name);
        EXPECT_NO_THROW(validate_floor_plan(b.plan, "generated"));
        EXPECT_EQ(test::interior_components_doors_open(b.plan, 0.2), 1);
      }
    }
  }
}

TEST(Generate, ApartmentHasTheUsualRooms) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const auto kinds = kind_counts(building(Archetype::kApartment, seed));
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_EQ(kinds.count("living"), 1u);
    EXPECT_EQ(kinds.count("kitchen"), 1u);
    EXPECT_EQ(kinds.count("bath"), 1u);
    EXPECT_EQ(kinds.count("hall"), 1u);
    ASSERT_EQ(kinds.count("bedroom"), 1u);
    EXPECT_GE(kinds.at("bedroom"), 2);
  }
}

TEST(Generate, AngledHasWallsAt30And45Degrees) {
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const GeneratedBuilding& b = building(Archetype::kAngled, seed);
    int at0 = 0, at30 = 0, at45 = 0, at60 = 0, other = 0;
    for (const Wall& w : b.plan.walls) {
      if (w.length_m() < 2.0) continue;  // short walls: rounding to 0.1 mm bends them slightly
      double deg = std::fmod(std::atan2(w.b_m.y() - w.a_m.y(), w.b_m.x() - w.a_m.x()) * 180.0 / kPi + 360.0, 90.0);
      if (deg > 89.99) deg -= 90.0;
      if (std::abs(deg) < 0.01) ++at0;
      else if (std::abs(deg - 30.0) < 0.01) ++at30;
      else if (std::abs(deg - 45.0) < 0.01) ++at45;
      else if (std::abs(deg - 60.0) < 0.01) ++at60;
      else ++other;  // hub facades between wings
    }
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_GT(at0, 5);
    EXPECT_GT(at30, 5);
    EXPECT_GT(at45, 5);
    EXPECT_LE(other, 4);
  }
}

TEST(Generate, ParametersChangeTheBuilding) {
  CampusParams small;
  small.target_area_min_m2 = 8500.0;
  small.target_area_max_m2 = 8500.0;
  CampusParams large;
  large.target_area_min_m2 = 14000.0;
  large.target_area_max_m2 = 14000.0;
  const double a_small = free_floor_area_m2(generate_campus(5, small).plan, 0.1);
  const double a_large = free_floor_area_m2(generate_campus(5, large).plan, 0.1);
  EXPECT_GT(a_large, a_small + 3000.0);
  EXPECT_GT(a_small, 8000.0);
  EXPECT_LT(a_large, 15000.0);

  BuildingStyle bare;
  bare.furniture = false;
  OfficeParams office;
  office.style = bare;
  EXPECT_TRUE(generate_office(3, office).plan.obstacles.empty());

  AngledParams fan;
  fan.wing_directions_deg = {0, 90, 225};
  const GeneratedBuilding b = generate_angled(2, fan);
  EXPECT_EQ(test::interior_components_doors_open(b.plan, 0.1), 1);
}

}  // namespace
}  // namespace floorcast

namespace floorcast {
namespace {

TEST(GenerateChecks, DetectBrokenBuildings) {
  // The checks above must be able to fail: remove the only door of the bathroom, or a piece of
  // the envelope, and they do.
  FloorPlan p = generate_apartment(1).plan;
  const auto bath_door = std::find_if(p.doors.begin(), p.doors.end(), [](const Door& d) {
    return d.id.rfind("door_bath_", 0) == 0;
  });
  ASSERT_NE(bath_door, p.doors.end());
  p.doors.erase(bath_door);
  EXPECT_EQ(test::interior_components_doors_open(p, 0.1), 2);

  FloorPlan q = generate_apartment(1).plan;
  const auto ext = std::find_if(q.walls.begin(), q.walls.end(), [](const Wall& w) { return w.id.rfind("ext", 0) == 0; });
  ASSERT_NE(ext, q.walls.end());
  const std::string ext_id = ext->id;
  q.windows.erase(std::remove_if(q.windows.begin(), q.windows.end(), [&](const Window& w) { return w.wall_id == ext_id; }),
                  q.windows.end());
  q.doors.erase(std::remove_if(q.doors.begin(), q.doors.end(), [&](const Door& d) { return d.wall_id == ext_id; }),
                q.doors.end());
  q.walls.erase(q.walls.begin() + (ext - q.walls.begin()));
  const test::EnvelopeRaster env = test::envelope_raster(q, 0.1);
  int leaking = 0;
  for (const GeneratedRoom& r : generate_apartment(1).rooms) {
    int row, col;
    ASSERT_TRUE(env.grid.world_to_cell(test::polygon_centroid(r.polygon_m), row, col));
    leaking += env.outside.at<std::uint8_t>(row, col) ? 1 : 0;
  }
  EXPECT_GT(leaking, 0);
}

}  // namespace
}  // namespace floorcast
