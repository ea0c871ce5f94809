// Issue 18: B-rep inputs are read in the helper process (domain/brep/IsolatedReading.h), so a
// crash or hang of OpenCASCADE becomes an InputError naming the input within the time limit;
// non-finite geometry and far-away models are refused before CGAL sees them.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <thread>

#include <unistd.h>

#include "RunControl.h"
#include "domain/BrepSolid.h"
#include "domain/CoordinateRange.h"
#include "input_errors.h"

using namespace oraclemesh;

namespace {

// A sphere of radius 5 at the origin as FreeCAD's exportBrep writes it.
const char* kSphereBrep = R"(DBRep_DrawableShape

CASCADE Topology V1, (c) Matra-Datavision
Locations 0
Curve2ds 4
1 0 1.5707963267948966 1 0 
1 6.2831853071795862 -6.2831853071795862 0 1 
1 0 -6.2831853071795862 0 1 
1 0 -1.5707963267948966 1 0 
Curves 1
2 0 0 0 -2.4492935982947064e-16 -1 0 1 -2.4492935982947064e-16 0 0 0 1 5
Polygon3D 0
PolygonOnTriangulations 0
Surfaces 1
4 CENTRE_X 0 0 0 0 1 1 0 -0 -0 1 0 5
Triangulations 0

TShapes 9
Ve
1e-07
3.06161699786838e-16 -7.49879891330929e-32 5
0 0

0101101
*
Ed
 1e-07 1 1 1
2  1 1 0 0 6.28318530717959
0

0101000
+9 0 -9 0 *
Ve
1e-07
3.06161699786838e-16 -7.49879891330929e-32 -5
0 0

0101101
*
Ed
 1e-07 1 1 0
1  1 0 4.71238898038469 7.85398163397448
3  2 3CN 1 0 4.71238898038469 7.85398163397448
0

0101000
-9 0 +7 0 *
Ed
 1e-07 1 1 1
2  4 1 0 0 6.28318530717959
0

0101000
+7 0 -7 0 *
Wi

0101100
-8 0 +6 0 +5 0 -6 0 *
Fa
0  1e-07 1 0

0111000
+4 0 *
Sh

0101100
+3 0 *
So

1100000
+2 0 *

+1 0 
)";

std::string sphereBrep(const std::string& centreX) {
  std::string text = kSphereBrep;
  text.replace(text.find("CENTRE_X"), 8, centreX);
  return text;
}

// Stands in for oraclemesh-shape-reader (ORACLEMESH_SHAPE_READER) while alive.
class FakeHelper {
 public:
  explicit FakeHelper(const std::string& script) {
    path_ = std::filesystem::temp_directory_path() /
            ("oraclemesh-fake-helper-" + std::to_string(::getpid()) + "-" + std::to_string(counter_++));
    std::ofstream(path_) << "#!/bin/sh\n" << script << "\n";
    std::filesystem::permissions(path_, std::filesystem::perms::owner_all);
    ::setenv("ORACLEMESH_SHAPE_READER", path_.c_str(), 1);
  }
  ~FakeHelper() {
    ::unsetenv("ORACLEMESH_SHAPE_READER");
    std::filesystem::remove(path_);
  }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

double secondsOf(const std::function<void()>& action) {
  const auto start = std::chrono::steady_clock::now();
  action();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

TEST(CoordinateRange, RefusesModelsTooFarFromTheOriginForTheirSize) {
  Bbox near;
  near.add(Point3{1e5, 0, 0});
  near.add(Point3{1e5 + 10, 10, 10});
  EXPECT_EQ(test::inputErrorOf([&] { requireCoordinateRange(near, "input 'a'"); }), "");
  Bbox far;
  far.add(Point3{1e20, 0, 0});
  far.add(Point3{1e20 + 10, 10, 10});
  const std::string message = test::inputErrorOf([&] { requireCoordinateRange(far, "input 'ball'"); });
  EXPECT_NE(message.find("input 'ball' lies 1e+20 model units from the origin"), std::string::npos) << message;
  EXPECT_NE(message.find("move the model near the origin"), std::string::npos) << message;
  Bbox huge;
  huge.add(Point3{-1e200, 0, 0});
  huge.add(Point3{1e200, 1, 1});
  // Beyond the coordinates the mesher computes with: a damaged file's unbounded geometry or the
  // wrong units; the message names both fixes.
  const std::string hugeMessage = test::inputErrorOf([&] { requireCoordinateRange(huge, "input 'h'"); });
  EXPECT_NE(hugeMessage.find("input 'h' has coordinates of 1e+200 model units"), std::string::npos) << hugeMessage;
  EXPECT_NE(hugeMessage.find("scale it to millimetres or metres"), std::string::npos) << hugeMessage;
  EXPECT_NE(hugeMessage.find("Part > Check geometry"), std::string::npos) << hugeMessage;
}

TEST(FiniteGeometry, NanInASurfaceIsRefusedNamingTheInputAndTheFace) {
  const TopoDS_Shape shape = readBrepText(sphereBrep("nan"), "input 'ball'", "");
  const std::string message = test::inputErrorOf([&] { BrepSolid::load(shape, "ball", BrepSolid::Grouping::Separate); });
  EXPECT_NE(message.find("input 'ball' has a non-finite number"), std::string::npos) << message;
  EXPECT_NE(message.find("face 1"), std::string::npos) << message;
}

TEST(IsolatedReading, LoadsTheSameSolidAsInProcess) {
  const RunControl control;
  const auto isolated = BrepSolid::loadBrepTextIsolated(sphereBrep("0"), "ball", BrepSolid::Grouping::Separate,
                                                        control, 0);
  const auto direct = BrepSolid::loadBrepText(sphereBrep("0"), "ball", BrepSolid::Grouping::Separate);
  ASSERT_EQ(isolated.solids.size(), 1u);
  EXPECT_NEAR(isolated.solids[0]->volume(), direct.solids[0]->volume(), 1e-9 * direct.solids[0]->volume());
  EXPECT_EQ(isolated.solids[0]->proxyInfo().triangles, direct.solids[0]->proxyInfo().triangles);
  EXPECT_TRUE(isolated.solids[0]->inside({1, 1, 1}));
  EXPECT_FALSE(isolated.solids[0]->inside({4, 4, 4}));
}

TEST(IsolatedReading, TheHelpersInputErrorComesBackAsItIs) {
  const RunControl control;
  const std::string message = test::inputErrorOf([&] {
    BrepSolid::loadBrepTextIsolated(sphereBrep("nan"), "ball", BrepSolid::Grouping::Separate, control, 0);
  });
  EXPECT_NE(message.find("input 'ball' has a non-finite number"), std::string::npos) << message;
}

TEST(IsolatedReading, ACrashOfTheReaderIsAnInputErrorNamingTheFile) {
  FakeHelper crashing("kill -SEGV $$");
  const RunControl control;
  const std::string message = test::inputErrorOf([&] {
    BrepSolid::loadFileIsolated("/data/bracket.step", "bracket", BrepSolid::Grouping::Separate, control, 0);
  });
  EXPECT_NE(message.find("OpenCASCADE crashed reading input 'bracket' (file '/data/bracket.step') (signal 11"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("Part > Check geometry or re-export it"), std::string::npos) << message;
}

TEST(IsolatedReading, AHangEndsAtTheTimeLimitAsAnInputError) {
  FakeHelper hanging("exec sleep 60");
  const RunControl control({}, 0.5);
  std::string message;
  const double seconds = secondsOf([&] {
    message = test::inputErrorOf([&] {
      BrepSolid::loadBrepTextIsolated(sphereBrep("0"), "ball", BrepSolid::Grouping::Separate, control, 0);
    });
  });
  EXPECT_LT(seconds, 5.0);
  EXPECT_NE(message.find("OpenCASCADE did not finish reading input 'ball' (BREP text) within limits.time_limit"),
            std::string::npos)
      << message;
}

TEST(IsolatedReading, CancelEndsTheReadAtOnce) {
  FakeHelper hanging("exec sleep 60");
  RunControl control;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    control.requestCancel();
  });
  bool cancelled = false;
  const double seconds = secondsOf([&] {
    try {
      BrepSolid::loadBrepTextIsolated(sphereBrep("0"), "ball", BrepSolid::Grouping::Separate, control, 0);
    } catch (const Cancelled&) {
      cancelled = true;
    }
  });
  canceller.join();
  EXPECT_TRUE(cancelled);
  EXPECT_LT(seconds, 5.0);
}
