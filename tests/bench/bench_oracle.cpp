// Benchmark of the B-rep oracle against OpenCASCADE on the shared CAD models: inside tests
// (BrepSolid::inside vs BRepClass3d_SolidClassifier, loaded once) and segment crossings
// (BrepSolid::crossings vs BRepIntCurveSurface_Inter, loaded once). Prints medians of
// several repetitions (the machine is shared and noisy) and the answers that disagree
// outside the 1e-7 x diagonal band around the surface (must be 0).
//
//   build/oraclemesh_bench_oracle [cad dir] [repetitions]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "Error.h"
#include "domain/BrepSolid.h"

#include "../cpp/occt_reference.h"

#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS_Compound.hxx>

namespace {

using namespace oraclemesh;

double seconds(const std::function<void()>& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// Distance from p to the faces of `shape` (BRepExtrema says 0 inside a solid).
double distanceToBoundary(const Point3& p, const TopoDS_Shape& shape) {
  BRep_Builder builder;
  TopoDS_Compound faces;
  builder.MakeCompound(faces);
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) builder.Add(faces, ex.Current());
  BRepExtrema_DistShapeShape dist(BRepBuilderAPI_MakeVertex(gp_Pnt(p[0], p[1], p[2])).Vertex(), faces);
  return dist.Value();
}

// Points/segments per measurement: enough for the reference to run about `budget` seconds.
int countFor(double referenceRate, double budget, int least, int most) {
  return std::clamp(static_cast<int>(referenceRate * budget), least, most);
}

struct Row {
  std::string model;
  int faces = 0;
  double insideOurs = 0, insideOcct = 0;
  int insideCompared = 0, insideDisagreeInBand = 0, insideDisagreeOutside = 0;
  double crossingsOurs = 0, crossingsOcct = 0;
  int segmentsCompared = 0, segmentsDisagree = 0, contradictionsLeftOut = 0;
};

Row benchmark(const BrepSolid& solid, int repetitions) {
  Row row;
  row.model = solid.name();
  row.faces = solid.faceCount();
  const double diagonal = solid.bbox().diagonal();
  const double tolerance = 1e-9 * diagonal;
  int solids = 0;
  for (TopExp_Explorer ex(solid.shape(), TopAbs_SOLID); ex.More(); ex.Next()) ++solids;

  // --- inside ---
  const std::vector<Point3> points = test::randomPointsAround(solid.bbox(), 100000, 7);
  test::ReferenceClassifier classifier(solid.shape(), tolerance);
  // Probe the reference's speed, then size the compared set to ~2 s of reference time.
  const int probe = 200;
  const double probeSeconds = seconds([&] {
    for (int i = 0; i < probe; ++i) classifier.inside(points[i]);
  });
  row.insideCompared = countFor(probe / probeSeconds, 2.0, 500, static_cast<int>(points.size()));
  std::vector<char> ours(points.size()), reference(row.insideCompared);
  std::vector<double> oursRates, occtRates;
  for (int r = 0; r < repetitions; ++r) {
    oursRates.push_back(points.size() / seconds([&] {
      for (size_t i = 0; i < points.size(); ++i) ours[i] = solid.inside(points[i]);
    }));
    occtRates.push_back(row.insideCompared / seconds([&] {
      for (int i = 0; i < row.insideCompared; ++i) reference[i] = classifier.inside(points[i]);
    }));
  }
  row.insideOurs = median(oursRates);
  row.insideOcct = median(occtRates);
  for (int i = 0; i < row.insideCompared; ++i) {
    if (ours[i] == reference[i]) continue;
    (distanceToBoundary(points[i], solid.shape()) < 1e-7 * diagonal ? row.insideDisagreeInBand
                                                                     : row.insideDisagreeOutside)++;
  }

  // --- crossings ---
  const std::vector<Point3> ends = test::randomPointsAround(solid.bbox(), 2 * 5000, 8);
  const int segments = static_cast<int>(ends.size() / 2);
  test::ReferenceIntersector intersector(solid.shape(), tolerance);
  const int segmentProbe = 50;
  const double segmentProbeSeconds = seconds([&] {
    for (int i = 0; i < segmentProbe; ++i) intersector.hits(ends[2 * i], ends[2 * i + 1]);
  });
  row.segmentsCompared = countFor(segmentProbe / segmentProbeSeconds, 2.0, 100, segments);
  std::vector<std::vector<BoundaryCrossing>> oursCrossings(segments);
  std::vector<std::vector<test::ReferenceIntersector::Hit>> referenceHits(row.segmentsCompared);
  oursRates.clear();
  occtRates.clear();
  for (int r = 0; r < repetitions; ++r) {
    oursRates.push_back(segments / seconds([&] {
      for (int i = 0; i < segments; ++i) oursCrossings[i] = solid.crossings(ends[2 * i], ends[2 * i + 1]);
    }));
    occtRates.push_back(row.segmentsCompared / seconds([&] {
      for (int i = 0; i < row.segmentsCompared; ++i) referenceHits[i] = intersector.hits(ends[2 * i], ends[2 * i + 1]);
    }));
  }
  row.crossingsOurs = median(oursRates);
  row.crossingsOcct = median(occtRates);
  for (int i = 0; i < row.segmentsCompared; ++i) {
    const test::CrossingComparison comparison =
        test::compareWithReference(oursCrossings[i], referenceHits[i], distance(ends[2 * i], ends[2 * i + 1]),
                                   1e-7 * diagonal, solids == 1);
    row.contradictionsLeftOut += comparison.contradictionsLeftOut;
    if (!comparison.mismatch.empty()) {
      ++row.segmentsDisagree;
      std::printf("  %s: segment %d: %s\n", row.model.c_str(), i, comparison.mismatch.c_str());
    }
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "../shared/data/cad";
  const int repetitions = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  std::vector<Row> rows;
  for (const char* file : {"part.step", "screw.step", "Kurbelwelle.stp", "U_Joint_2.stp", "presse_asm.step"}) {
    try {
      const auto solid = BrepSolid::fromFile(dir + "/" + file, file);
      rows.push_back(benchmark(*solid, repetitions));
      std::fflush(stdout);
    } catch (const InputError& e) {
      std::printf("%s: not loaded (%s)\n", file, e.what());
    }
  }
  std::printf("\nMedians of %d repetitions. inside: 100000 random points in the bounding box grown by 10%%; "
              "crossings: 5000 random segments there. OCCT answers on the first N of them (N in brackets).\n\n",
              repetitions);
  std::printf("| model | faces | inside/s BrepSolid | inside/s OCCT [N] | ratio | disagree (band / outside) "
              "| crossings/s BrepSolid | crossings/s OCCT [N] | ratio | segments disagreeing |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  int failures = 0;
  for (const Row& r : rows) {
    std::printf("| %s | %d | %.0f | %.0f [%d] | %.0fx | %d / %d | %.0f | %.0f [%d] | %.0fx | %d |\n", r.model.c_str(),
                r.faces, r.insideOurs, r.insideOcct, r.insideCompared, r.insideOurs / r.insideOcct,
                r.insideDisagreeInBand, r.insideDisagreeOutside, r.crossingsOurs, r.crossingsOcct, r.segmentsCompared,
                r.crossingsOurs / r.crossingsOcct, r.segmentsDisagree);
    failures += r.insideDisagreeOutside + r.segmentsDisagree;
  }
  return failures == 0 ? 0 : 1;
}
