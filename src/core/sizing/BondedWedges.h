#pragma once
// Where two parts rest on each other tangentially (a rod or a ball on a plate, a rounded edge
// on a face) the empty space beside their contact is a wedge that narrows to nothing. Keeping
// it open to where it is as narrow as the contact tolerance would ask for sizes without bound
// (a gap of width w asks for facets of w). Such a wedge is bonded where it is narrower than a
// fraction of the size the geometry asks there and closes within a few such sizes, as a
// contact line of any mesh bonds over an element or so. Beyond the line where the faces stop
// facing each other (15 degrees, GeometrySizes.cpp) a wedge is no gap anyway, so for a tangent
// contact of the usual proportions all of the gap is bonded; the space filled is at most about
// 0.2 % of a cylinder's volume on a plane (x^3 / 3R per unit length, x = R sin 15 degrees,
// the same at every radius). Gaps between faces that face each other (a clearance, two boxes
// apart) are no wedge and are kept open at every width.
//
// BondedWedges holds the places found bonded so (GapRays in sizing/GeometrySizes.cpp): the
// refinement's contact criteria, Rule Set T's terminator and the self-check's joined-parts
// test read the width bonded at a point from it.
#include <cstddef>
#include <unordered_map>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

// A wedge is bonded where it is narrower than this fraction of the local size ...
constexpr double kWedgeBondPerSize = 0.3;
// ... and closes (its width over the angle between its faces) within this many local sizes.
constexpr double kWedgeClosingPerSize = 2.0;

struct BondedWedgeSample {
  Point3 at{};         // on a face beside the contact
  double width = 0;    // the widest gap bonded there
  double reach = 0;    // how far from `at` that width holds (the local size)
  int entry = -1, other = -1;  // the two oracle entries, entry < other
};

class BondedWedges {
 public:
  explicit BondedWedges(std::vector<BondedWedgeSample> samples);

  // The widest gap bonded at p: the largest width of the samples within their reach of p,
  // 0 where no wedge is bonded.
  double widthAt(const Point3& p) const;

  const std::vector<BondedWedgeSample>& samples() const { return samples_; }

 private:
  struct CellKey {
    long long x, y, z;
    bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct CellHash {
    size_t operator()(const CellKey& k) const;
  };
  CellKey cellOf(const Point3& p) const;

  std::vector<BondedWedgeSample> samples_;
  double cell_ = 0;  // the largest reach: a query looks at its own cell and the 26 around it
  std::unordered_map<CellKey, std::vector<size_t>, CellHash> grid_;
};

}  // namespace oraclemesh
