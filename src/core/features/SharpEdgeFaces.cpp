#include "features/SharpEdgeFaces.h"

#include <algorithm>

#include "domain/BrepTopology.h"

namespace oraclemesh {

std::set<std::tuple<int, int, int>> facesMeetingAlongCurves(const HierarchicalOracle& oracle,
                                                            const FeatureGraph& features,
                                                            const std::vector<int>& curves) {
  std::set<std::tuple<int, int, int>> pairs;
  for (const FeaturePolyline& pl : features.polylines) {
    if (pl.source < 0 || pl.edge < 0 || pl.source >= static_cast<int>(oracle.entries().size())) continue;
    if (std::find(curves.begin(), curves.end(), pl.curve) == curves.end()) continue;
    const BrepTopology* topology = oracle.entries()[pl.source].source->brepTopology();
    if (!topology) continue;
    const std::vector<int>& faces = topology->facesOfEdge(pl.edge);
    for (size_t a = 0; a < faces.size(); ++a)
      for (size_t b = a + 1; b < faces.size(); ++b)
        if (faces[a] != faces[b]) pairs.emplace(pl.source, std::min(faces[a], faces[b]), std::max(faces[a], faces[b]));
  }
  return pairs;
}

}  // namespace oraclemesh
