// Sizes from the geometry of inputs without exact faces (issue 16 item 1): a triangle surface
// and a voxel image at the default fineness get sizes from their discrete curvature, thickness
// and gaps, so a small part in a large model keeps its volume and parts that do not touch stay
// apart, as B-rep parts do (pipeline_size_field.cpp).
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeBox.hxx>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "job/Pipeline.h"
#include "discrete_shapes.h"
#include "mesh_checks.h"
#include "occt_checks.h"

namespace oraclemesh {
namespace {

using nlohmann::json;

// At fineness "off" the small parts below lose volume: the self-check must say so.
JobResult runWithFineness(json job, const std::string& fineness) {
  if (!fineness.empty()) job["criteria"] = {{"fineness", fineness}};
  job["checks"] = "warn";  // the meshes at "off" are kept to be compared
  return runJob(JobSpec::fromJson(job, ""), RunControl());
}

// A pin of radius 3 (48 facets) through a 200 mm block: the default cap (diagonal / 15, 19 mm)
// is six times the pin's radius.
TEST(SizeFieldDiscrete, ASmallTriangleSurfacePinInALargeBlockKeepsItsVolumeAtTheDefault) {
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(200, 200, 40).Shape();
  const json job = {{"inputs",
                     {test::surfaceInput("pin", test::tessellatedCylinder({100, 100, -10}, 3, 60, 48), 1),
                      {{"name", "block"}, {"brep", test::brepText(block)}, {"material", 2}}}},
                    {"element_order", 2},  // mid nodes on the facets: the volume is the surface's
                    {"seed", 0}};
  const double pin = test::tessellatedCylinderVolume(3, 60, 48);
  const JobResult r = runWithFineness(job, "");
  const double meshed = test::volumePerMaterial(r.mesh)[1];
  const JobResult off = runWithFineness(job, "off");
  const double meshedOff = test::volumePerMaterial(off.mesh)[1];
  std::cout << "[ figures  ] triangle-surface pin: " << meshed << " at the default (" << r.mesh.tets.size()
            << " tets), " << meshedOff << " with fineness off, of " << pin << "\n";
  EXPECT_EQ(r.report.at("criteria").at("fineness"), "moderate");
  EXPECT_GT(r.report.at("criteria").at("size_field").at("samples").at("curvature").get<int>(), 0);
  EXPECT_NEAR(meshed, pin, 0.005 * pin);
  EXPECT_GT(std::abs(meshedOff - pin), 0.02 * pin) << "the cap alone keeps the pin: the test shows nothing";
  EXPECT_FALSE(off.report.at("self_check").at("problems").empty());
}

// Two triangle-surface cubes half a millimetre apart: the gap between them gets sizes (cells of
// 1.4 mm at the cap would reach across and join them).
TEST(SizeFieldDiscrete, TriangleSurfaceCubesHalfAMillimetreApartStayApart) {
  const json job = {{"inputs",
                     {test::surfaceInput("lower", test::triangleBox({0, 0, 0}, 10, 10, 10), 1),
                      test::surfaceInput("upper", test::triangleBox({0, 0, 10.5}, 10, 10, 10), 2)}},
                    {"element_order", 1},
                    {"optimize", {{"perturb", false}}},
                    {"seed", 0}};
  for (const std::string fineness : {"", "off"}) {
    const JobResult r = runWithFineness(job, fineness);
    const json& gaps = r.report.at("criteria").at("gap_sizes");
    ASSERT_EQ(gaps.at("gaps").size(), 1u) << fineness << gaps.dump(1);
    EXPECT_NEAR(gaps.at("gaps")[0].at("width").get<double>(), 0.5, 1e-9);
    EXPECT_TRUE(r.report.at("self_check").at("joined").empty()) << fineness << r.report.at("self_check").dump(1);
    EXPECT_TRUE(r.report.at("interfaces").empty()) << fineness;
    // A triangle surface has no sharp edges kept: the cubes' edges are cut a little.
    const auto volumes = test::volumePerMaterial(r.mesh);
    EXPECT_NEAR(volumes.at(1), 1000, 10) << fineness;
    EXPECT_NEAR(volumes.at(2), 1000, 10) << fineness;
  }
}

// A ball of radius 4 voxels (label 1) in a 60 x 60 x 12 voxel slab (label 2), 1 mm voxels: the
// cap (diagonal / 15, 5.7 mm) is wider than the ball; its curvature asks for about 1 mm. The
// reference is the region's volume at converged sizes.
TEST(SizeFieldDiscrete, ASmallVoxelBallInALargeImageKeepsItsVolumeAtTheDefault) {
  const int nx = 60, ny = 60, nz = 12;
  std::string labels(static_cast<size_t>(nx) * ny * nz, '\2');
  int64_t ballVoxels = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        if (std::hypot(i - 30.0, j - 30.0, k - 5.5) <= 4) {
          labels[i + nx * (j + ny * k)] = '\1';
          ++ballVoxels;
        }
  const std::string path = (std::filesystem::temp_directory_path() / "oraclemesh_ball_in_slab.nrrd").string();
  {
    std::ofstream out(path, std::ios::binary);
    out << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: " << nx << " " << ny << " " << nz
        << "\nspacings: 1 1 1\nencoding: raw\n\n"
        << labels;
  }
  const json job = {{"inputs", {{{"name", "scan"}, {"image", path}, {"materials", {{"1", 1u}, {"2", 2u}}}}}},
                    {"element_order", 2},
                    {"seed", 0}};
  const JobResult r = runWithFineness(job, "");
  const JobResult off = runWithFineness(job, "off");
  // The region's own volume (the interpolated boundary's, not the voxels'): converged sizes.
  json fine = job;
  fine["criteria"] = {{"fineness", "off"},
                      {"materials", {{"1", {{"cell_size", 0.4}, {"facet_size", 0.4}, {"facet_distance", 0.01}}}}}};
  const JobResult reference = runJob(JobSpec::fromJson(fine, ""), RunControl());
  std::filesystem::remove(path);
  const double region = test::volumePerMaterial(reference.mesh)[1], meshed = test::volumePerMaterial(r.mesh)[1],
               meshedOff = test::volumePerMaterial(off.mesh)[1];
  std::cout << "[ figures  ] voxel ball: " << meshed << " at the default (" << r.mesh.tets.size() << " tets), "
            << meshedOff << " with fineness off, " << region << " at size 0.4 (" << reference.mesh.tets.size()
            << " tets), " << ballVoxels << " voxels\n";
  EXPECT_GT(r.report.at("criteria").at("size_field").at("samples").at("curvature").get<int>(), 0);
  EXPECT_NEAR(meshed, region, 0.005 * region);
  // The self-check measures the region the mesher meshes (rays through the interpolated
  // boundary), not the voxel count, which is 2.8 % more for so small a ball.
  const json& checked = r.report.at("self_check").at("materials").at("1");
  EXPECT_NEAR(checked.at("input_volume").get<double>(), region, 0.005 * region) << checked.dump();
  EXPECT_LT(checked.at("input_volume_error_bar").get<double>(), 0.01 * region) << checked.dump();
  EXPECT_GT(std::abs(meshedOff - region), 0.03 * region);
  EXPECT_FALSE(off.report.at("self_check").at("problems").empty());
}

}  // namespace
}  // namespace oraclemesh
