#pragma once
// Which two faces of a B-rep meet along given feature curves: the refiner's criterion for
// facets that jump over a sharp edge beside a small dihedral angle (refine/FacetCriteria.h)
// asks it.
#include <set>
#include <tuple>
#include <vector>

#include "domain/HierarchicalOracle.h"
#include "features/FeatureGraph.h"

namespace oraclemesh {

// (oracle entry, smaller face index, larger face index) for every two distinct faces adjacent
// to a B-rep edge that a polyline of `features` with one of `curves` runs along (junction,
// user and triangle-surface polylines have no faces of their own and add nothing).
std::set<std::tuple<int, int, int>> facesMeetingAlongCurves(const HierarchicalOracle& oracle,
                                                            const FeatureGraph& features,
                                                            const std::vector<int>& curves);

}  // namespace oraclemesh
