#pragma once
// OpenCASCADE's own answers, used as the reference for the oracle by the tests and by the
// benchmark (no GoogleTest here): point classification composed by priority, line/face
// intersections, plus the random points and the demo assembly they are asked about.
#include <gtest/gtest.h>

#include <cctype>
#include <BRepAdaptor_Surface.hxx>
#include <BRepClass3d_SolidClassifier.hxx>
#include <BRepIntCurveSurface_Inter.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <GeomAdaptor_Curve.hxx>
#include <Geom_Line.hxx>
#include <IntCurveSurface_TransitionOnCurve.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Ax2.hxx>

#include <algorithm>
#include <memory>
#include <random>
#include <vector>

#include <string>

#include "Geometry.h"
#include "domain/Source.h"

namespace oraclemesh::test {

// `count` points uniformly in `box` grown by 10% of its size on every side (fixed seed).
inline std::vector<Point3> randomPointsAround(const Bbox& box, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Point3> points;
  points.reserve(count);
  for (int i = 0; i < count; ++i) {
    Point3 p;
    for (int a = 0; a < 3; ++a) {
      const double w = box.max[a] - box.min[a];
      p[a] = box.min[a] - 0.1 * w + 1.2 * w * unit(rng);
    }
    points.push_back(p);
  }
  return points;
}

// The walking skeleton's demo: a pin through a plate (the pin wins the overlap by priority)
// and a box cutting one corner of the plate. Priority order: pin, cut, plate.
struct DemoAssembly {
  TopoDS_Shape pin = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(30, 30, -10), gp_Dir(0, 0, 1)), 5, 30).Shape();
  TopoDS_Shape plate = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 100, 60, 10).Shape();
  TopoDS_Shape cut = BRepPrimAPI_MakeBox(gp_Pnt(80, 40, -5), 30, 30, 20).Shape();
};

// BRepClass3d_SolidClassifier loaded once per solid of a shape (Load is the costly part).
// Not thread-safe: one instance per thread.
class ReferenceClassifier {
 public:
  ReferenceClassifier(const TopoDS_Shape& shape, double tolerance) : tolerance_(tolerance) {
    for (TopExp_Explorer ex(shape, TopAbs_SOLID); ex.More(); ex.Next()) {
      classifiers_.push_back(std::make_unique<BRepClass3d_SolidClassifier>());
      classifiers_.back()->Load(ex.Current());
    }
  }
  // Inside or on the boundary of any solid of the shape.
  bool inside(const Point3& p) {
    for (auto& c : classifiers_) {
      c->Perform(gp_Pnt(p[0], p[1], p[2]), tolerance_);
      if (c->State() == TopAbs_IN || c->State() == TopAbs_ON) return true;
    }
    return false;
  }

 private:
  double tolerance_;
  std::vector<std::unique_ptr<BRepClass3d_SolidClassifier>> classifiers_;
};

// Inputs in priority order, each a shape with a material id (0 = cut), labelled as the
// hierarchical oracle documents it: the first input containing p decides.
class ReferenceLabeler {
 public:
  struct Input {
    TopoDS_Shape shape;
    int material;  // 0 for a cut
  };
  ReferenceLabeler(const std::vector<Input>& inputs, double tolerance) {
    for (const Input& input : inputs) {
      materials_.push_back(input.material);
      classifiers_.push_back(std::make_unique<ReferenceClassifier>(input.shape, tolerance));
    }
  }
  int label(const Point3& p) {
    for (size_t i = 0; i < classifiers_.size(); ++i)
      if (classifiers_[i]->inside(p)) return materials_[i];
    return 0;
  }

 private:
  std::vector<int> materials_;
  std::vector<std::unique_ptr<ReferenceClassifier>> classifiers_;
};

// BRepIntCurveSurface_Inter loaded once with a shape; every hit of a segment with a face,
// sorted by t. Hits on an edge come once per face; tangent hits are marked. `entering` is
// read off the face's outward normal at the hit.
class ReferenceIntersector {
 public:
  struct Hit {
    double t;
    int face;  // 0-based TopExp::MapShapes index
    bool tangent;
    bool entering;
  };
  ReferenceIntersector(const TopoDS_Shape& shape, double tolerance) {
    intersector_.Load(shape, tolerance);
    TopExp::MapShapes(shape, TopAbs_FACE, faces_);
  }
  std::vector<Hit> hits(const Point3& a, const Point3& b) {
    std::vector<Hit> result;
    const Point3 d = b - a;
    const double length = norm(d);
    if (length == 0) return result;
    Handle(Geom_Line) line = new Geom_Line(gp_Pnt(a[0], a[1], a[2]), gp_Dir(d[0], d[1], d[2]));
    intersector_.Init(GeomAdaptor_Curve(line, 0.0, length));
    for (; intersector_.More(); intersector_.Next()) {
      gp_Pnt p;
      gp_Vec du, dv;
      BRepAdaptor_Surface(intersector_.Face()).D1(intersector_.U(), intersector_.V(), p, du, dv);
      gp_Vec normal = du.Crossed(dv);
      if (intersector_.Face().Orientation() == TopAbs_REVERSED) normal.Reverse();
      result.push_back({intersector_.W() / length, faces_.FindIndex(intersector_.Face()) - 1,
                        intersector_.Transition() == IntCurveSurface_Tangent,
                        normal.X() * d[0] + normal.Y() * d[1] + normal.Z() * d[2] < 0});
    }
    std::sort(result.begin(), result.end(), [](const Hit& x, const Hit& y) { return x.t < y.t; });
    return result;
  }

 private:
  BRepIntCurveSurface_Inter intersector_;
  TopTools_IndexedMapOfShape faces_;
};

// A second opinion on a point where the classifier is in doubt: the parity of the boundary
// crossings (BRepIntCurveSurface_Inter) of rays from p to beyond the box, in three skew
// directions. Returns 1 (inside) or 0 when the three rays agree, -1 when they do not.
inline int insideByRayParity(const TopoDS_Shape& shape, const Point3& p, double reach, double tolerance) {
  ReferenceIntersector intersector(shape, tolerance);
  const Point3 directions[3] = {{0.8017, 0.2672, 0.5345}, {-0.3015, 0.9045, -0.3015}, {0.2182, -0.4364, -0.8729}};
  int votes[2] = {0, 0};
  for (const Point3& d : directions) {
    int places = 0;
    double last = -1;
    for (const auto& hit : intersector.hits(p, p + reach * d)) {
      if (hit.tangent) continue;
      if (last < 0 || (hit.t - last) * reach > 1e3 * tolerance) ++places;  // an edge hit counts once
      last = hit.t;
    }
    ++votes[places % 2];
  }
  return votes[0] == 3 ? 0 : votes[1] == 3 ? 1 : -1;
}

// How crossings() compares with the reference hits of the same segment. The reference
// lists an edge hit once per face, so hits within `close` (along the segment) are one place;
// each crossing must match the next place in t (within `close`) and in face (any face hit
// there). Places left without a crossing are allowed only where the reference contradicts
// itself (two entries or two exits in a row along a single solid), which OpenCASCADE does on
// a few grazing B-spline faces and crossings() resolves with the classifier.
struct CrossingComparison {
  std::string mismatch;  // empty when they agree
  int contradictionsLeftOut = 0;
};

inline CrossingComparison compareWithReference(const std::vector<BoundaryCrossing>& ours,
                                               const std::vector<ReferenceIntersector::Hit>& hits, double length,
                                               double close, bool singleSolid) {
  CrossingComparison result;
  std::vector<std::vector<ReferenceIntersector::Hit>> places;
  for (const auto& hit : hits) {
    if (hit.tangent) continue;
    if (places.empty() || (hit.t - places.back().front().t) * length > close) places.emplace_back();
    places.back().push_back(hit);
  }
  auto contradictory = [&](size_t j) {
    const bool sense = places[j].front().entering;
    return singleSolid && ((j > 0 && places[j - 1].front().entering == sense) ||
                           (j + 1 < places.size() && places[j + 1].front().entering == sense));
  };
  auto describe = [&](const char* what, double t, int face) {
    return std::string(what) + " at t = " + std::to_string(t) + " on face " + std::to_string(face);
  };
  size_t j = 0;
  for (const BoundaryCrossing& c : ours) {
    auto matches = [&](size_t k) {
      if (std::abs(c.t - places[k].front().t) * length > close) return false;
      for (const auto& hit : places[k])
        if (hit.face == c.patch) return true;
      return false;
    };
    while (j < places.size() && !matches(j) && contradictory(j)) {
      ++result.contradictionsLeftOut;
      ++j;
    }
    if (j == places.size()) {
      result.mismatch = describe("crossing", c.t, c.patch) + " is not in the reference";
      return result;
    }
    if (!matches(j)) {
      result.mismatch = describe("crossing", c.t, c.patch) + " but " +
                        describe("reference", places[j].front().t, places[j].front().face);
      return result;
    }
    ++j;
  }
  for (; j < places.size(); ++j) {
    if (!contradictory(j)) {
      result.mismatch = describe("reference crossing", places[j].front().t, places[j].front().face) + " is missing";
      return result;
    }
    ++result.contradictionsLeftOut;
  }
  return result;
}

// The shared CAD models that hold solids (cube_filet.stp is an open shell), for the
// parameterised agreement tests, and a test name made of a file name.
inline const char* const kSolidModels[] = {"part.step", "screw.step", "Kurbelwelle.stp", "U_Joint_2.stp",
                                           "presse_asm.step"};
inline std::string modelTestName(const ::testing::TestParamInfo<const char*>& info) {
  std::string name = info.param;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

}  // namespace oraclemesh::test
