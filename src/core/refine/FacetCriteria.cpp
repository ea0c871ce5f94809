#include "refine/FacetCriteria.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace oraclemesh::refine {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// The kernel's own constructions, as the refiner's triangulation uses them, so the measures
// round the same way there and here.
K::Point_3 kernelPoint(const Point3& p) { return K::Point_3(p[0], p[1], p[2]); }

}  // namespace

double FacetSizeCriterion::ballRadius(const FacetShape& f) {
  return std::sqrt(CGAL::squared_distance(kernelPoint(f.ballCentre), kernelPoint(f.corners[0])));
}

double FacetDistanceCriterion::distance(const FacetShape& f) {
  const K::Point_3 fc =
      CGAL::circumcenter(kernelPoint(f.corners[0]), kernelPoint(f.corners[1]), kernelPoint(f.corners[2]));
  return std::sqrt(CGAL::squared_distance(fc, kernelPoint(f.ballCentre)));
}

double FacetAngleCriterion::smallestAngleDeg(const FacetShape& f) {
  double minAngle = 180;
  for (int k = 0; k < 3; ++k) {
    const K::Vector_3 e1 = kernelPoint(f.corners[(k + 1) % 3]) - kernelPoint(f.corners[k]);
    const K::Vector_3 e2 = kernelPoint(f.corners[(k + 2) % 3]) - kernelPoint(f.corners[k]);
    const double cosine = CGAL::scalar_product(e1, e2) / std::sqrt(e1.squared_length() * e2.squared_length());
    minAngle = std::min(minAngle, std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / M_PI);
  }
  return minAngle;
}

bool FacetAcrossSharpEdgeCriterion::fails(const FacetShape& f) const {
  if (!f.acrossSharpEdge) return false;
  return !(depthBound > 0 && std::isfinite(depthBound)) || FacetDistanceCriterion::distance(f) > depthBound;
}

bool FacetAngleCriterion::applies() const { return bound > 0 && std::isfinite(bound); }

double FacetCriteria::bound(const FacetShape& f, double MaterialCriteria::*field) const {
  double bound = std::numeric_limits<double>::infinity();
  for (int m : {f.labelA, f.labelB})
    if (m > 0) bound = std::min(bound, table_.of(m).*field);
  return bound;
}

double FacetCriteria::bound(const FacetShape& f, const CriteriaTable::FieldValues& at,
                            double (CriteriaTable::*size)(int, const CriteriaTable::FieldValues&) const) const {
  double bound = std::numeric_limits<double>::infinity();
  for (int m : {f.labelA, f.labelB})
    if (m > 0) bound = std::min(bound, (table_.*size)(m, at));
  return bound;
}

FacetVerdict FacetCriteria::judge(const FacetShape& f, bool withAngle, const CriteriaTable::FieldValues* below) const {
  if (FacetOnBoundaryCriterion().fails(f)) {
    FacetVerdict v;
    v.badness = FacetOnBoundaryCriterion::kExcess;
    v.reason = "a vertex not on the boundary";
    return v;
  }
  // A bound of 0 would read as "criterion off", so only positive bounds may decide.
  if (below && below->field > 0 && below->gap > 0) {
    FacetVerdict v = judgeWith(f, withAngle, *below);
    if (v.badness == 0) return v;
  }
  return judgeWith(f, withAngle, table_.fieldsAt(f.ballCentre));
}

FacetVerdict FacetCriteria::judgeWith(const FacetShape& f, bool withAngle, const CriteriaTable::FieldValues& at) const {
  FacetVerdict v;
  double worst = 0;
  const double r = FacetSizeCriterion::ballRadius(f);
  const FacetSizeCriterion size{bound(f, at, &CriteriaTable::facetSize)};
  if (size.fails(r)) {
    worst = r / size.bound;
    v.reason = "surface Delaunay ball radius above facet_size";
  }
  const FacetDistanceCriterion distance{bound(f, at, &CriteriaTable::facetDistance)};
  if (distance.bound > 0) {
    const double d = FacetDistanceCriterion::distance(f);
    if (d > distance.bound && d / distance.bound > worst) {
      worst = d / distance.bound;
      v.reason = "facet distance above facet_distance";
    }
  }
  const FacetAngleCriterion angle{std::min(bound(f, &MaterialCriteria::facet_angle), FacetAngleCriterion::kCap)};
  if (withAngle && angle.applies()) {
    const double minAngle = FacetAngleCriterion::smallestAngleDeg(f);
    if (minAngle < angle.bound && angle.bound / std::max(minAngle, 1e-9) > worst) {
      worst = angle.bound / std::max(minAngle, 1e-9);
      v.reason = "facet angle below facet_angle";
    }
  }
  const FacetBridgeCriterion bridge{table_.contact_tolerance};
  if (bridge.fails(f) && FacetBridgeCriterion::kExcess > worst) {
    worst = FacetBridgeCriterion::kExcess;
    v.reason = "its dual edge crosses empty space between two parts wider than the contact tolerance";
  }
  const FacetOnInterfaceCriterion onInterface{table_.contact_tolerance};
  if (onInterface.fails(f) && FacetOnInterfaceCriterion::kExcess > worst) {
    worst = FacetOnInterfaceCriterion::kExcess;
    v.reason = "a corner farther than the contact tolerance from one of the two parts it lies between";
  }
  const FacetAcrossSharpEdgeCriterion acrossEdge{FacetAcrossSharpEdgeCriterion::kDepthShare * distance.bound};
  if (acrossEdge.fails(f) && FacetAcrossSharpEdgeCriterion::kExcess > worst) {
    worst = FacetAcrossSharpEdgeCriterion::kExcess;
    v.reason = "it spans the wedge beside a dihedral angle under 60 degrees deeper than half the facet distance";
  }
  v.badness = worst > 1 ? worst : 0;
  return v;
}

}  // namespace oraclemesh::refine
