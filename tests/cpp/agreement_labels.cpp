// The hierarchical oracle's labels against OpenCASCADE on 10,000 random points per model
// (100,000 in the benchmark run, ORACLEMESH_AGREEMENT_POINTS=100000: tests/bench/README.md):
// BRepClass3d_SolidClassifier (loaded once per solid, two threads) composed by priority
// must give the same label everywhere except within 1e-7 x diagonal of an input boundary.
// Where they differ farther out, a second opinion decides: the parity of ray crossings
// (BRepIntCurveSurface_Inter) in three directions; a disagreement is a failure unless the
// rays unanimously side with the oracle (then the classifier is wrong there, and the test
// says so). Its own executable and ctest entries: the reference is slow on B-spline models
// (about 100-200 points/s on U_Joint_2); ORACLEMESH_AGREEMENT_SECONDS limits each model to
// the points the classifier answers within that time, in a fixed order, for quick runs.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <map>
#include <thread>

#include "Error.h"
#include "domain/BrepSolid.h"
#include "domain/HierarchicalOracle.h"

#include "occt_checks.h"
#include "occt_reference.h"

namespace oraclemesh {
namespace {

// ORACLEMESH_AGREEMENT_POINTS overrides the count. 10,000 keeps U_Joint_2 near a minute in
// every test run; the benchmark compares 100,000.
int pointCount() {
  const char* value = std::getenv("ORACLEMESH_AGREEMENT_POINTS");
  return value && std::atoi(value) > 0 ? std::atoi(value) : 10000;
}

// Seconds of reference time per model (ORACLEMESH_AGREEMENT_SECONDS, e.g. 30 for a quick
// run by hand). The default, 0, compares every point: about 9 minutes for U_Joint_2 at
// 100,000 points.
double referenceBudget() {
  const char* value = std::getenv("ORACLEMESH_AGREEMENT_SECONDS");
  return value && *value ? std::atof(value) : 0.0;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void expectLabelsAgree(const std::string& what, const HierarchicalOracle& oracle,
                       const std::vector<test::ReferenceLabeler::Input>& inputs, unsigned seed) {
  const int count = pointCount();
  const double diagonal = oracle.diagonal();
  const std::vector<Point3> points = test::randomPointsAround(oracle.bbox(), count, seed);

  auto start = std::chrono::steady_clock::now();
  std::vector<int> ours(points.size());
  for (size_t i = 0; i < points.size(); ++i) ours[i] = oracle.label(points[i]);
  const double oursSeconds = secondsSince(start);

  // Two threads, each with its own classifiers (an instance is not thread-safe), taking
  // the points in order until the budget is spent.
  start = std::chrono::steady_clock::now();
  const double budget = referenceBudget();
  std::vector<int> reference(points.size(), -1);
  auto work = [&](size_t first) {
    test::ReferenceLabeler labeler(inputs, 1e-9 * diagonal);
    for (size_t i = first; i < points.size(); i += 2) {
      if (budget > 0 && i % 64 < 2 && secondsSince(start) > budget) break;
      reference[i] = labeler.label(points[i]);
    }
  };
  std::thread second(work, 1);
  work(0);
  second.join();
  const double referenceSeconds = secondsSince(start);
  size_t compared = 0;
  while (compared < points.size() && reference[compared] >= 0) ++compared;

  int inBand = 0, classifierWrong = 0, outside = 0;
  std::map<int, int> perLabel;
  for (size_t i = 0; i < compared; ++i) {
    ++perLabel[ours[i]];
    if (ours[i] == reference[i]) continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& input : inputs) nearest = std::min(nearest, test::distanceToShape(points[i], input.shape));
    if (nearest < 1e-7 * diagonal) {
      ++inBand;
      continue;
    }
    // Second opinion: the inputs' memberships by ray parity, composed by priority.
    int byRays = 0;
    bool unanimous = true;
    for (const auto& input : inputs) {
      const int in = test::insideByRayParity(input.shape, points[i], 3 * diagonal, 1e-9 * diagonal);
      unanimous &= in >= 0;
      if (in == 1) {
        byRays = input.material;
        break;
      }
    }
    if (unanimous && byRays == ours[i]) {
      ++classifierWrong;
      std::cout << "[ note     ] " << what << ": BRepClass3d_SolidClassifier says " << reference[i] << " at ("
                << points[i][0] << ", " << points[i][1] << ", " << points[i][2] << "), " << nearest
                << " from the nearest boundary; ray parity in three directions agrees with the oracle's " << ours[i]
                << "\n";
      continue;
    }
    ++outside;
    ADD_FAILURE() << what << ": label " << ours[i] << " but OpenCASCADE says " << reference[i] << " at ("
                  << points[i][0] << ", " << points[i][1] << ", " << points[i][2] << "), " << nearest
                  << " from the nearest boundary";
    if (outside > 20) break;
  }
  EXPECT_GE(perLabel.size(), 2u) << "all points got the same label: the test would prove nothing";
  EXPECT_GE(compared, std::min<size_t>(points.size(), 1000)) << "the reference answered too few points";
  // BRepClass3d_SolidClassifier misclassifies a few points off U_Joint_2's B-spline faces
  // (6 of 100,000, 1.7-3.4 mm from the surface, where three ray-parity tests agree with the
  // oracle); more than 1 in 10,000 would mean the second opinion itself is off.
  EXPECT_LE(classifierWrong, 2 + static_cast<int>(compared / 10000)) << "the classifier is wrong that often? look closer";
  std::cout << "[ figures  ] " << what << ": label() " << count / oursSeconds << " points/s on " << count
            << " points; BRepClass3d_SolidClassifier by priority (2 threads) " << compared / referenceSeconds
            << " points/s, " << compared << " points compared in " << referenceSeconds << " s; " << inBand
            << " disagreements within 1e-7 x diagonal of a boundary, " << classifierWrong
            << " where ray parity shows the classifier wrong, " << outside << " others\n";
}

class SharedModel : public ::testing::TestWithParam<const char*> {};

TEST_P(SharedModel, LabelsAgreeWithClassifier) {
  const std::string file = GetParam();
  // One input per solid, in file order (presse_asm.step: 16 solids by priority, its open
  // shells left out with a warning), each its own material.
  const auto loaded = BrepSolid::loadFile(test::cadDir() + "/" + file, file, BrepSolid::Grouping::Separate);
  std::vector<OracleEntry> entries;
  std::vector<test::ReferenceLabeler::Input> reference;
  for (size_t i = 0; i < loaded.solids.size(); ++i) {
    entries.push_back({loaded.solids[i], Role::Material, static_cast<int>(i) + 1});
    reference.push_back({loaded.solids[i]->shape(), static_cast<int>(i) + 1});
  }
  const HierarchicalOracle oracle(entries);
  expectLabelsAgree(file, oracle, reference, 61);
}

INSTANTIATE_TEST_SUITE_P(Cad, SharedModel, ::testing::ValuesIn(test::kSolidModels), test::modelTestName);

TEST(AssemblyLabels, DemoAssemblyAgreesWithClassifier) {
  const test::DemoAssembly parts;
  const HierarchicalOracle oracle({{std::make_shared<BrepSolid>(parts.pin, "pin"), Role::Material, 1},
                                   {std::make_shared<BrepSolid>(parts.cut, "cut"), Role::Cut, 0},
                                   {std::make_shared<BrepSolid>(parts.plate, "plate"), Role::Material, 2}});
  expectLabelsAgree("demo assembly", oracle, {{parts.pin, 1}, {parts.cut, 0}, {parts.plate, 2}}, 62);
}

}  // namespace
}  // namespace oraclemesh
