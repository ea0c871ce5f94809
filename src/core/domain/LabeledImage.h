#pragma once
// Labeled voxel images (segmented CT/MR scans, the thesis' bones): a 3D grid of integer
// labels, label 0 = background. Each label the job maps to a material becomes one oracle
// entry (ImageLabelRegion); all regions of one image share the grid.
//
// Where is the boundary of a label between voxel centres? We use the "majority" of the
// trilinearly interpolated label indicators: a point belongs to label L when the trilinear
// weight of the cell corners labelled L exceeds the weight of every other label (background
// and unmapped labels included). Why this choice:
// - Between two labels only it is exactly the 0.5 level set of L's interpolated indicator:
//   a smooth surface (inside each cell) that cuts every grid edge between an L voxel and a
//   non-L voxel at its midpoint, i.e. at the voxel face. The enclosed volume therefore
//   matches the voxel count up to second-order terms (for a ball of radius 10 voxels the
//   difference is well under 1%), which is what FEM users compare against.
// - Unlike one 0.5 level set per label, the regions of different labels are disjoint and
//   leave no gaps where three labels meet (the 0.5 level sets of three labels all miss a
//   small sliver there): two touching bones share one interface, so their order in the
//   oracle does not matter.
// - It needs only the 8 corner labels of one cell: no smoothing of the whole image, no
//   parameters, deterministic.
// Points outside the grid are background, so a label touching the image border is closed
// by the border voxels' outer faces.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "domain/Source.h"

namespace oraclemesh {

class LabeledImage {
 public:
  // Voxel (i, j, k) has its centre at origin + (i sx, j sy, k sz); labels are stored with i
  // fastest (index i + nx (j + ny k)). `description` names the image in messages ("the image
  // 'labels.nrrd' of input 'scan'"). InputError on a non-positive spacing or a size mismatch.
  LabeledImage(std::array<int64_t, 3> size, Point3 spacing, Point3 origin, std::vector<int32_t> labels,
               std::string description);

  const std::array<int64_t, 3>& size() const { return size_; }
  const Point3& spacing() const { return spacing_; }
  const Point3& origin() const { return origin_; }
  const std::string& description() const { return description_; }
  double voxelVolume() const { return spacing_[0] * spacing_[1] * spacing_[2]; }
  // Label of voxel (i, j, k); 0 outside the grid.
  int32_t at(int64_t i, int64_t j, int64_t k) const;
  // Number of voxels of every label present (background included).
  const std::map<int32_t, int64_t>& labelCounts() const { return counts_; }
  // Index box of the voxels of `label` (min and max voxel index per axis).
  std::pair<std::array<int64_t, 3>, std::array<int64_t, 3>> indexBox(int32_t label) const;
  // 6-connected component id of voxel (i, j, k) among the voxels of its label; -1 outside.
  int32_t component(int64_t i, int64_t j, int64_t k) const;

  // The interpolated field of `label` at p: weight of `label` minus the largest weight of
  // another label (> 0 inside, 0 on the boundary, in [-1, 1]), its gradient (world units),
  // and that other label (the one across the boundary).
  struct Margin {
    double value = 0;
    Point3 gradient{};
    int32_t other = 0;
  };
  Margin margin(int32_t label, const Point3& p) const;

 private:
  std::array<int64_t, 3> size_;
  Point3 spacing_, origin_;
  std::vector<int32_t> labels_;
  std::vector<int32_t> components_;
  std::map<int32_t, int64_t> counts_;
  std::map<int32_t, std::pair<std::array<int64_t, 3>, std::array<int64_t, 3>>> boxes_;
  std::string description_;
};

// The region of one label of a LabeledImage, as an oracle input.
class ImageLabelRegion : public Source {
 public:
  // InputError when the label has no voxel in the image.
  ImageLabelRegion(std::shared_ptr<const LabeledImage> image, int32_t label, std::string name);
  ~ImageLabelRegion() override;

  const std::string& name() const override { return name_; }
  int32_t label() const { return label_; }
  const LabeledImage& image() const { return *image_; }
  Bbox bbox() const override { return bbox_; }
  bool inside(const Point3& p) const override;
  // Nearest boundary point; patch = the label across the boundary (0 = background).
  BoundaryProjection project(const Point3& p) const override;
  // Voxel face centres (exactly on the boundary: the field is linear along a grid edge and
  // 0 at its midpoint), about `spacing` apart, at least one per pair of touching connected
  // components, so every boundary component is seeded.
  std::vector<BoundarySample> boundarySamples(double spacing) const override;
  // Crossings on the interpolated field: the segment is split where it crosses the cell
  // walls (the field is a cubic in t inside one cell, kinked across walls), each piece is
  // sampled and every sign change bisected to 1e-9 of the voxel size.
  std::vector<BoundaryCrossing> crossings(const Point3& a, const Point3& b) const override;
  // Voxel count x voxel volume: what a user checks the mesh against.
  double volume() const override;

 private:
  struct FaceIndex;
  std::shared_ptr<const LabeledImage> image_;
  int32_t label_;
  std::string name_;
  Bbox bbox_;
  std::unique_ptr<FaceIndex> faces_;  // boundary voxel faces, for nearest-point queries
};

// One region per label of `materialOfLabel` (label -> material), in label order, with the
// image's input name. InputError naming the image and the labels present when a mapped label
// has no voxel, or none of them has.
std::vector<std::pair<std::shared_ptr<const ImageLabelRegion>, int>> makeImageRegions(
    const std::shared_ptr<const LabeledImage>& image, const std::map<int32_t, int>& materialOfLabel,
    const std::string& inputName);

}  // namespace oraclemesh
