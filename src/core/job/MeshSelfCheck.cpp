#include "job/MeshSelfCheck.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <sstream>

#include "domain/BrepTopology.h"
#include "domain/LabeledImage.h"
#include "mesh/Topology.h"

namespace oraclemesh {

namespace {

// Rays per side of the grid across an overlap box (two jittered rays per cell).
constexpr int kRays = 32;

Bbox intersection(const Bbox& a, const Bbox& b) {
  Bbox r;
  if (a.empty() || b.empty()) return r;
  for (int i = 0; i < 3; ++i) {
    r.min[i] = std::max(a.min[i], b.min[i]);
    r.max[i] = std::min(a.max[i], b.max[i]);
    if (r.min[i] > r.max[i]) return Bbox{};
  }
  return r;
}

double boxVolume(const Bbox& b) {
  return b.empty() ? 0.0 : (b.max[0] - b.min[0]) * (b.max[1] - b.min[1]) * (b.max[2] - b.min[2]);
}

// Parameter intervals [t0, t1] of the segment a->b inside a source, from its exact crossings.
using Intervals = std::vector<std::array<double, 2>>;

Intervals insideIntervals(const Source& source, const Point3& a, const Point3& b) {
  const std::vector<BoundaryCrossing> crossings = source.crossings(a, b);
  Intervals inside;
  if (crossings.empty()) {
    const Point3 middle{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
    if (source.inside(middle)) inside.push_back({0.0, 1.0});
    return inside;
  }
  double start = crossings.front().entering ? -1.0 : 0.0;  // -1: outside where the segment starts
  for (const BoundaryCrossing& c : crossings) {
    if (c.entering) {
      start = c.t;
    } else if (start >= 0.0) {
      inside.push_back({start, c.t});
      start = -1.0;
    }
  }
  if (start >= 0.0) inside.push_back({start, 1.0});
  return inside;
}

// Length (in t) of the part of `inside` that `cover` covers; `cover` may overlap itself.
double lengthOfIntersection(const Intervals& inside, Intervals cover) {
  std::sort(cover.begin(), cover.end());
  Intervals merged;
  for (const auto& c : cover) {
    if (!merged.empty() && c[0] <= merged.back()[1]) merged.back()[1] = std::max(merged.back()[1], c[1]);
    else merged.push_back(c);
  }
  double length = 0;
  for (const auto& i : inside)
    for (const auto& c : merged) length += std::max(0.0, std::min(i[1], c[1]) - std::max(i[0], c[0]));
  return length;
}

// A volume measured along rays: along z through `region`, two jittered ones per cell of a
// kRays x kRays grid; `length(from, to)` is the length of the ray inside what is measured (cut
// exactly by the sources' own crossings, so the error is only in the grid). The pair's
// difference estimates each cell's variance, so the error bar reflects the cells the outline
// passes through; pairs that agree contribute nothing, so the bar keeps half a cell's column
// of the region for a volume thin enough to pass between all rays. Seeded: the same job gives
// the same report.
struct RayEstimate {
  double volume = 0;
  double error_bar = 0;
};

template <class Length>
RayEstimate alongRays(const Bbox& region, uint64_t seed, const Length& length) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double dx = (region.max[0] - region.min[0]) / kRays, dy = (region.max[1] - region.min[1]) / kRays;
  auto ray = [&](int i, int j) {
    const double x = region.min[0] + (i + unit(random)) * dx, y = region.min[1] + (j + unit(random)) * dy;
    return length(Point3{x, y, region.min[2]}, Point3{x, y, region.max[2]});
  };
  double sum = 0, variance = 0;
  for (int i = 0; i < kRays; ++i)
    for (int j = 0; j < kRays; ++j) {
      const double a = ray(i, j), b = ray(i, j);
      sum += a + b;
      variance += (a - b) * (a - b) / 4.0;  // of the pair's mean: s^2 / 2 with s^2 = (a - b)^2 / 2
    }
  const double cellArea = dx * dy;
  return {cellArea * sum / 2.0,
          std::max(3.0 * cellArea * std::sqrt(variance), boxVolume(region) / (2.0 * kRays * kRays))};
}

// The part of entry `e` that a higher-priority entry (material or cut) takes from it.
struct Overlap {
  double volume = 0;
  double error_bar = 0;
  bool found = false;     // some ray ran inside e and inside a higher entry
};

Overlap overlapWithHigherEntries(const HierarchicalOracle& oracle, size_t e) {
  const auto& entries = oracle.entries();
  const Source& source = *entries[e].source;
  const Bbox own = source.bbox();
  // Parts that touch along a plane share a box of no thickness (up to the CAD's rounding):
  // no overlap to look for there.
  const double flat = 1e-6 * oracle.diagonal();
  Bbox region;
  std::vector<size_t> higher;
  for (size_t h = 0; h < e; ++h) {
    const Bbox common = intersection(own, entries[h].source->bbox());
    if (common.empty() || std::min({common.max[0] - common.min[0], common.max[1] - common.min[1],
                                    common.max[2] - common.min[2]}) <= flat)
      continue;
    region.add(common);
    higher.push_back(h);
  }
  Overlap overlap;
  if (higher.empty()) return overlap;

  const RayEstimate taken = alongRays(region, 0x5e1fc4ecULL + e, [&](const Point3& from, const Point3& to) {
    const Intervals inside = insideIntervals(source, from, to);
    if (inside.empty()) return 0.0;
    Intervals above;
    for (size_t h : higher) {
      const Bbox& box = entries[h].source->bbox();
      if (from[0] < box.min[0] || from[0] > box.max[0] || from[1] < box.min[1] || from[1] > box.max[1]) continue;
      const Intervals more = insideIntervals(*entries[h].source, from, to);
      above.insert(above.end(), more.begin(), more.end());
    }
    return (to[2] - from[2]) * lengthOfIntersection(inside, above);
  });
  overlap.volume = taken.volume;
  overlap.error_bar = taken.error_bar;
  overlap.found = overlap.volume > 1e-6 * source.volume();  // more than rounding where faces touch
  return overlap;
}

// The volume the mesher meshes of a source whose volume() is not its boundary's: an image
// label's voxel count, where the boundary interpolates between voxel centres (for a ball of
// 4 voxels' radius, 2.8 % less than the voxels).
RayEstimate meshedRegionVolume(const Source& source, uint64_t seed) {
  return alongRays(source.bbox(), seed, [&](const Point3& from, const Point3& to) {
    double inside = 0;
    for (const auto& i : insideIntervals(source, from, to)) inside += i[1] - i[0];
    return (to[2] - from[2]) * inside;
  });
}

std::string partNames(const std::vector<std::string>& names) {
  std::ostringstream out;
  const size_t shown = names.size() <= 3 ? names.size() : 2;
  for (size_t i = 0; i < shown; ++i) out << (i ? ", " : "") << "'" << names[i] << "'";
  if (shown < names.size()) out << " and " << names.size() - shown << " more";
  return out.str();
}

std::string percent(double fraction) {
  std::ostringstream out;
  out.precision(fraction < 0.1 ? 2 : 3);
  out << 100.0 * fraction << " %";
  return out.str();
}

}  // namespace

MeshSelfCheck checkMeshAgainstInputs(const TetMesh& mesh, const HierarchicalOracle& oracle,
                                     const std::map<int, double>& volume_per_material, double contact_tolerance,
                                     const std::vector<double>& distance_kept_off_cad,
                                     const BondedWedges* bonded_wedges) {
  MeshSelfCheck check;
  check.contact_tolerance = contact_tolerance > 0 ? contact_tolerance : 1e-6 * oracle.diagonal();
  struct Entries {
    std::vector<std::string> names;
    bool piecesKnown = true;  // every entry a B-rep solid that nothing higher cuts into
  };
  std::map<int, Entries> ofMaterial;
  const auto& entries = oracle.entries();
  for (size_t e = 0; e < entries.size(); ++e) {
    if (entries[e].role != Role::Material) continue;
    const int m = entries[e].material;
    MaterialVolumeCheck& c = check.materials[m];
    const Overlap overlap = overlapWithHigherEntries(oracle, e);
    c.error_bar += overlap.error_bar;
    if (dynamic_cast<const ImageLabelRegion*>(entries[e].source.get())) {
      const RayEstimate region = meshedRegionVolume(*entries[e].source, 0x1abe1ULL + e);
      c.input_volume += region.volume - overlap.volume;
      c.error_bar += region.error_bar;
    } else {
      c.input_volume += entries[e].source->volume() - overlap.volume;
    }
    Entries& of = ofMaterial[m];
    of.names.push_back(entries[e].source->name());
    // A B-rep entry is one connected solid; a cut or a higher entry through it may split it.
    of.piecesKnown = of.piecesKnown && entries[e].source->brepTopology() != nullptr && !overlap.found;
  }
  const std::map<int, int64_t> components = componentsPerMaterial(mesh);
  for (auto& [m, c] : check.materials) {
    const Entries& of = ofMaterial[m];
    c.parts = partNames(of.names);
    const auto v = volume_per_material.find(m);
    c.mesh_volume = v == volume_per_material.end() ? 0.0 : v->second;
    const auto k = components.find(m);
    c.components = k == components.end() ? 0 : k->second;
    c.max_components = of.piecesKnown ? static_cast<int64_t>(of.names.size()) : -1;
    const std::string who = "material " + std::to_string(m) + " (" + c.parts + ")";
    const std::string key = " (criteria.materials.\"" + std::to_string(m) + "\")";
    const std::string finer = "give it a smaller cell_size and facet_size" + key;
    // Linear elements cut curved faces short by their chords; quadratic ones put their mid
    // nodes on the CAD.
    const std::string finerOrQuadratic = (mesh.order() == 1 ? "mesh with element_order 2 or " : "") + finer;
    if (c.input_volume <= c.error_bar) continue;  // all of it taken by higher entries or cuts
    c.deviation = (c.mesh_volume - c.input_volume) / c.input_volume;
    const double allowed = std::max(check.volume_tolerance, c.error_bar / c.input_volume);
    std::ostringstream figures;
    figures << "(mesh " << c.mesh_volume << ", input " << c.input_volume;
    if (c.error_bar > 0) figures << " +- " << c.error_bar;
    figures << " model units^3)";
    if (c.mesh_volume == 0)
      check.problems.push_back(who + " is missing from the mesh " + figures.str() + ": it is smaller than its elements; " +
                               finer);
    else if (c.deviation < -allowed)
      check.problems.push_back(who + " has " + percent(-c.deviation) + " less volume in the mesh than in the input " +
                               figures.str() + ": its elements are too large for it; " + finerOrQuadratic);
    else if (c.deviation > allowed)
      check.problems.push_back(who + " has " + percent(c.deviation) + " more volume in the mesh than in the input " +
                               figures.str() + ": the mesh fills gaps or hollows of it; give it a smaller " +
                               "facet_distance and facet_size" + key);
    if (c.max_components >= 0 && c.components > c.max_components)
      check.problems.push_back(who + " is meshed as " + std::to_string(c.components) + " separate pieces but is " +
                               std::to_string(c.max_components) + " solid(s) in the input: parts of it are thinner " +
                               "than its elements; " + finer);
  }
  check.interface_gaps = measureInterfaceGaps(mesh, oracle, check.contact_tolerance, distance_kept_off_cad,
                                              bonded_wedges);
  check.joined = joinedPairs(check.interface_gaps);
  for (const JoinedAcrossGap& j : check.joined) {
    if (j.joined_area <= check.volume_tolerance * j.interface_area) continue;
    std::ostringstream message;
    message << "materials " << j.material << " (" << check.materials[j.material].parts << ") and " << j.other_material
            << " (" << check.materials[j.other_material].parts << ") are joined across a gap: "
            << percent(j.joined_area / j.interface_area) << " of the mesh faces between them (" << j.joined_area
            << " of " << j.interface_area << " model units^2) have a node up to " << j.widest_gap
            << " away from one of the parts (near (" << j.widest_at[0] << ", " << j.widest_at[1] << ", "
            << j.widest_at[2] << ")), so the mesh bonds parts that do not touch; give them a cell_size and facet_size "
            << "near the gap's width (criteria.materials), or close or widen the gap in the CAD";
    check.problems.push_back(message.str());
  }
  return check;
}

}  // namespace oraclemesh
