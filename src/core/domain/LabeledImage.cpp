#include "domain/LabeledImage.h"

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>
#include <unordered_set>

#include "Error.h"

namespace oraclemesh {

namespace {

constexpr double kMaxSpacingRatio = 1000;
constexpr int kAxisSteps[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

std::string labelList(const std::map<int32_t, int64_t>& counts) {
  std::string list;
  int shown = 0;
  for (const auto& [label, n] : counts) {
    if (label == 0) continue;
    if (shown++ == 20) return list + ", ...";
    list += (list.empty() ? "" : ", ") + std::to_string(label);
  }
  return list.empty() ? "none, the image is all background (0)" : list;
}

}  // namespace

LabeledImage::LabeledImage(std::array<int64_t, 3> size, Point3 spacing, Point3 origin, std::vector<int32_t> labels,
                           std::string description)
    : size_(size), spacing_(spacing), origin_(origin), labels_(std::move(labels)), description_(std::move(description)) {
  for (int a = 0; a < 3; ++a) {
    if (!(std::isfinite(spacing_[a]) && spacing_[a] > 0))
      throw InputError(description_ + " has voxel spacing " + std::to_string(spacing_[a]) + " along axis " +
                       std::to_string(a) + ": give positive voxel sizes in model units (mm)");
    if (!std::isfinite(origin_[a]))
      throw InputError(description_ + " has a non-finite origin: give the centre of the first voxel as three numbers");
    if (size_[a] <= 0)
      throw InputError(description_ + " has no voxels along axis " + std::to_string(a) + ": give a 3D image");
  }
  // Far from cubic voxels the field's cells are needles: crossings and projections lose the
  // precision they are bisected to (and a mesh of such an image is no use anyway).
  const double finest = std::min({spacing_[0], spacing_[1], spacing_[2]});
  const double coarsest = std::max({spacing_[0], spacing_[1], spacing_[2]});
  if (coarsest > kMaxSpacingRatio * finest)
    throw InputError(description_ + " has voxels " + std::to_string(coarsest / finest) +
                     " times longer along one axis than along another (spacing " + std::to_string(spacing_[0]) + ", " +
                     std::to_string(spacing_[1]) + ", " + std::to_string(spacing_[2]) + "): resample it to voxels at "
                     "most " + std::to_string(int(kMaxSpacingRatio)) + " times longer than wide, and check the "
                     "spacing units");
  if (static_cast<int64_t>(labels_.size()) != size_[0] * size_[1] * size_[2])
    throw InputError(description_ + " holds " + std::to_string(labels_.size()) + " labels for " +
                     std::to_string(size_[0]) + " x " + std::to_string(size_[1]) + " x " + std::to_string(size_[2]) +
                     " voxels: the data does not match the sizes");

  // Counts, index boxes and 6-connected components of every label, in one sweep with a
  // flood fill per new component (an explicit stack: components can have millions of voxels).
  components_.assign(labels_.size(), -1);
  int32_t nextComponent = 0;
  std::vector<int64_t> stack;
  const int64_t nx = size_[0], ny = size_[1];
  for (int64_t k = 0, v = 0; k < size_[2]; ++k)
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i, ++v) {
        const int32_t label = labels_[v];
        ++counts_[label];
        auto [box, added] = boxes_.try_emplace(label, std::array<int64_t, 3>{i, j, k}, std::array<int64_t, 3>{i, j, k});
        auto& [lo, hi] = box->second;
        const int64_t idx[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], idx[a]);
          hi[a] = std::max(hi[a], idx[a]);
        }
        if (components_[v] >= 0) continue;
        const int32_t id = nextComponent++;
        components_[v] = id;
        stack.assign(1, v);
        while (!stack.empty()) {
          const int64_t w = stack.back();
          stack.pop_back();
          const int64_t wi = w % nx, wj = (w / nx) % ny, wk = w / (nx * ny);
          for (const auto& step : kAxisSteps) {
            const int64_t a = wi + step[0], b = wj + step[1], c = wk + step[2];
            if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= size_[2]) continue;
            const int64_t u = a + nx * (b + ny * c);
            if (components_[u] < 0 && labels_[u] == label) {
              components_[u] = id;
              stack.push_back(u);
            }
          }
        }
      }
}

int32_t LabeledImage::at(int64_t i, int64_t j, int64_t k) const {
  if (i < 0 || j < 0 || k < 0 || i >= size_[0] || j >= size_[1] || k >= size_[2]) return 0;
  return labels_[i + size_[0] * (j + size_[1] * k)];
}

int32_t LabeledImage::component(int64_t i, int64_t j, int64_t k) const {
  if (i < 0 || j < 0 || k < 0 || i >= size_[0] || j >= size_[1] || k >= size_[2]) return -1;
  return components_[i + size_[0] * (j + size_[1] * k)];
}

std::pair<std::array<int64_t, 3>, std::array<int64_t, 3>> LabeledImage::indexBox(int32_t label) const {
  auto it = boxes_.find(label);
  if (it == boxes_.end()) return {{0, 0, 0}, {-1, -1, -1}};
  return it->second;
}

LabeledImage::Margin LabeledImage::margin(int32_t label, const Point3& p) const {
  // Cell = the 8 voxel centres around p; trilinear weights of its corners grouped by label.
  int64_t base[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    const double u = (p[a] - origin_[a]) / spacing_[a];
    const double fl = std::floor(u);
    base[a] = static_cast<int64_t>(std::clamp(fl, -2.0, static_cast<double>(size_[a]) + 1));
    f[a] = std::clamp(u - fl, 0.0, 1.0);
    if (fl != static_cast<double>(base[a])) f[a] = fl < 0 ? 0.0 : 1.0;  // far outside: background anyway
  }
  int32_t cornerLabel[8];
  double weight[8];
  Point3 gradient[8];
  int groups = 0;
  for (int c = 0; c < 8; ++c) {
    const int d[3] = {c & 1, (c >> 1) & 1, (c >> 2) & 1};
    double w[3], dw[3];
    for (int a = 0; a < 3; ++a) {
      w[a] = d[a] ? f[a] : 1 - f[a];
      dw[a] = (d[a] ? 1.0 : -1.0) / spacing_[a];
    }
    const int32_t l = at(base[0] + d[0], base[1] + d[1], base[2] + d[2]);
    const double weightHere = w[0] * w[1] * w[2];
    const Point3 gradientHere{dw[0] * w[1] * w[2], w[0] * dw[1] * w[2], w[0] * w[1] * dw[2]};
    int g = 0;
    while (g < groups && cornerLabel[g] != l) ++g;
    if (g == groups) {
      cornerLabel[g] = l;
      weight[g] = 0;
      gradient[g] = {0, 0, 0};
      ++groups;
    }
    weight[g] += weightHere;
    gradient[g] = gradient[g] + gradientHere;
  }
  double own = 0;
  Point3 ownGradient{0, 0, 0};
  int strongest = -1;
  for (int g = 0; g < groups; ++g) {
    if (cornerLabel[g] == label) {
      own = weight[g];
      ownGradient = gradient[g];
    } else if (strongest < 0 || weight[g] > weight[strongest] ||
               (weight[g] == weight[strongest] && cornerLabel[g] < cornerLabel[strongest])) {
      strongest = g;  // ties go to the smaller label: deterministic
    }
  }
  Margin m;
  if (strongest < 0) {  // all 8 corners carry `label`
    m.value = 1;
    m.other = 0;
    return m;
  }
  m.value = own - weight[strongest];
  m.gradient = ownGradient - gradient[strongest];
  m.other = cornerLabel[strongest];
  return m;
}

// Boundary voxel face centres of one label in a kd-tree: the start of nearest-point queries
// far from the boundary, where following the field's gradient does not work (it is flat).
struct ImageLabelRegion::FaceIndex {
  using Kernel = CGAL::Simple_cartesian<double>;
  using Traits = CGAL::Search_traits_3<Kernel>;
  using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
  Search::Tree tree;
};

ImageLabelRegion::~ImageLabelRegion() = default;

ImageLabelRegion::ImageLabelRegion(std::shared_ptr<const LabeledImage> image, int32_t label, std::string name)
    : image_(std::move(image)), label_(label), name_(std::move(name)), faces_(std::make_unique<FaceIndex>()) {
  const auto [lo, hi] = image_->indexBox(label_);
  if (hi[0] < lo[0])
    throw InputError(name_ + ": label " + std::to_string(label_) + " has no voxel in " + image_->description());
  // The region lies in the cells that have an L corner: within one voxel of the L voxels.
  const Point3& s = image_->spacing();
  const Point3& o = image_->origin();
  for (int a = 0; a < 3; ++a) {
    bbox_.min[a] = o[a] + (static_cast<double>(lo[a]) - 1) * s[a];
    bbox_.max[a] = o[a] + (static_cast<double>(hi[a]) + 1) * s[a];
  }
  std::vector<FaceIndex::Kernel::Point_3> centres;
  for (int64_t k = lo[2]; k <= hi[2]; ++k)
    for (int64_t j = lo[1]; j <= hi[1]; ++j)
      for (int64_t i = lo[0]; i <= hi[0]; ++i) {
        if (image_->at(i, j, k) != label_) continue;
        for (const auto& step : kAxisSteps) {
          if (image_->at(i + step[0], j + step[1], k + step[2]) == label_) continue;
          centres.emplace_back(o[0] + (i + 0.5 * step[0]) * s[0], o[1] + (j + 0.5 * step[1]) * s[1],
                               o[2] + (k + 0.5 * step[2]) * s[2]);
        }
      }
  faces_->tree.insert(centres.begin(), centres.end());
  faces_->tree.build();  // built now: queries must be const and thread-safe
}

bool ImageLabelRegion::inside(const Point3& p) const {
  // A NaN coordinate would become an out-of-range voxel index (the conversion is undefined).
  return isFinite(p) && image_->margin(label_, p).value > 0;
}

double ImageLabelRegion::volume() const {
  auto it = image_->labelCounts().find(label_);
  return static_cast<double>(it->second) * image_->voxelVolume();
}

BoundaryProjection ImageLabelRegion::project(const Point3& p) const {
  if (!isFinite(p)) return {};
  const Point3& s = image_->spacing();
  const double voxel = std::min({s[0], s[1], s[2]});
  BoundaryProjection best;
  // Near the boundary (mesh vertices Mesh_3 put there, mid-edge nodes) Newton's method on the
  // field along its gradient lands on the boundary next to p: the nearest point up to the
  // curvature of the surface over the (tiny) distance moved.
  Point3 x = p;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const LabeledImage::Margin m = image_->margin(label_, x);
    if (std::abs(m.value) < 1e-13) {
      best.point = x;
      best.patch = m.other;
      best.distance = distance(p, x);
      break;
    }
    const double g2 = dot(m.gradient, m.gradient);
    if (g2 * voxel * voxel < 1e-12) break;  // flat: deep inside or far outside
    Point3 next = x - (m.value / g2) * m.gradient;
    // Steps that cross a cell wall can overshoot where the field kinks: damp until the field
    // shrinks, and give up (to the face centres below) if it will not.
    for (int halving = 0; halving < 20 && std::abs(image_->margin(label_, next).value) >= std::abs(m.value); ++halving)
      next = x + 0.5 * (next - x);
    x = next;
    if (distance(p, x) > 3 * voxel) break;
  }
  // Far from the boundary: the nearest boundary voxel face centre (exactly on the boundary,
  // at most half a voxel diagonal farther than the true nearest point).
  const FaceIndex::Kernel::Point_3 query(p[0], p[1], p[2]);  // the search keeps a reference to it
  FaceIndex::Search search(faces_->tree, query, 1);
  if (search.begin() != search.end()) {
    const auto nearest = *search.begin();  // a value: the iterator hands out temporaries
    const auto& q = nearest.first;
    const Point3 face{q.x(), q.y(), q.z()};
    const double d = distance(p, face);
    if (d < best.distance) {
      best.point = face;
      best.distance = d;
      best.patch = image_->margin(label_, face).other;
    }
  }
  return best;
}

std::vector<BoundarySample> ImageLabelRegion::boundarySamples(double spacing) const {
  const Point3& s = image_->spacing();
  const Point3& o = image_->origin();
  const auto [lo, hi] = image_->indexBox(label_);
  const double bucket = std::isfinite(spacing) && spacing > 0 ? spacing : std::min({s[0], s[1], s[2]});
  // One face per bucket of side `spacing` and per pair of components it separates, so that
  // a small component (or a cavity) next to a large one still gets its own sample.
  std::set<std::tuple<int64_t, int64_t, int64_t, int32_t, int32_t, int32_t>> taken;
  std::vector<BoundarySample> samples;
  for (int64_t k = lo[2]; k <= hi[2]; ++k)
    for (int64_t j = lo[1]; j <= hi[1]; ++j)
      for (int64_t i = lo[0]; i <= hi[0]; ++i) {
        if (image_->at(i, j, k) != label_) continue;
        for (const auto& step : kAxisSteps) {
          const int64_t a = i + step[0], b = j + step[1], c = k + step[2];
          const int32_t other = image_->at(a, b, c);
          if (other == label_) continue;
          const Point3 centre{o[0] + (i + 0.5 * step[0]) * s[0], o[1] + (j + 0.5 * step[1]) * s[1],
                              o[2] + (k + 0.5 * step[2]) * s[2]};
          const auto key = std::make_tuple(static_cast<int64_t>(std::floor(centre[0] / bucket)),
                                           static_cast<int64_t>(std::floor(centre[1] / bucket)),
                                           static_cast<int64_t>(std::floor(centre[2] / bucket)),
                                           image_->component(i, j, k), other, image_->component(a, b, c));
          if (!taken.insert(key).second) continue;
          samples.push_back({centre, {double(step[0]), double(step[1]), double(step[2])}, other});
        }
      }
  return samples;
}

std::vector<BoundaryCrossing> ImageLabelRegion::crossings(const Point3& a, const Point3& b) const {
  std::vector<BoundaryCrossing> result;
  if (!isFinite(a) || !isFinite(b)) return result;
  const double length = distance(a, b);
  if (length == 0.0) return result;
  const Point3& s = image_->spacing();
  const Point3& o = image_->origin();
  // Clip to the region's box: outside it the field is negative everywhere.
  double t0 = 0, t1 = 1;
  for (int axis = 0; axis < 3; ++axis) {
    const double d = b[axis] - a[axis];
    if (d == 0) {
      if (a[axis] < bbox_.min[axis] || a[axis] > bbox_.max[axis]) return result;
      continue;
    }
    double lo = (bbox_.min[axis] - a[axis]) / d, hi = (bbox_.max[axis] - a[axis]) / d;
    if (lo > hi) std::swap(lo, hi);
    t0 = std::max(t0, lo);
    t1 = std::min(t1, hi);
  }
  if (t0 > t1) return result;
  // Pieces between cell walls (planes through voxel centres).
  std::vector<double> breaks{t0, t1};
  for (int axis = 0; axis < 3; ++axis) {
    const double d = b[axis] - a[axis];
    if (d == 0) continue;
    const double u0 = (a[axis] + t0 * d - o[axis]) / s[axis], u1 = (a[axis] + t1 * d - o[axis]) / s[axis];
    for (double w = std::ceil(std::min(u0, u1)); w <= std::max(u0, u1); w += 1) {
      const double t = (o[axis] + w * s[axis] - a[axis]) / d;
      if (t > t0 && t < t1) breaks.push_back(t);
    }
  }
  std::sort(breaks.begin(), breaks.end());
  const double tolerance = 1e-9 * std::min({s[0], s[1], s[2]});
  auto at = [&](double t) { return a + t * (b - a); };
  auto field = [&](double t) { return image_->margin(label_, at(t)).value; };
  constexpr int kStepsPerPiece = 4;  // a cubic has at most 3 roots per piece
  double previousT = t0;
  double previous = field(t0);
  for (size_t piece = 0; piece + 1 < breaks.size(); ++piece) {
    const double from = breaks[piece], to = breaks[piece + 1];
    if (to <= from) continue;
    for (int step = 1; step <= kStepsPerPiece; ++step) {
      const double t = from + (to - from) * step / kStepsPerPiece;
      const double value = field(t);
      if ((value > 0) != (previous > 0)) {
        double lo = previousT, hi = t;
        const bool wasInside = previous > 0;
        // Also ends where doubles cannot halve the interval any more (a long segment, a fine
        // tolerance), which would otherwise loop for ever.
        for (int halving = 0; halving < 200 && (hi - lo) * length > tolerance; ++halving) {
          const double mid = 0.5 * (lo + hi);
          ((field(mid) > 0) == wasInside ? lo : hi) = mid;
        }
        BoundaryCrossing crossing;
        crossing.t = 0.5 * (lo + hi);
        crossing.point = at(crossing.t);
        crossing.entering = !wasInside;
        // The label across the boundary: the one just outside the region along the segment.
        crossing.patch = image_->margin(label_, at(wasInside ? hi : lo)).other;
        result.push_back(crossing);
      }
      previous = value;
      previousT = t;
    }
  }
  return result;
}

std::vector<std::pair<std::shared_ptr<const ImageLabelRegion>, int>> makeImageRegions(
    const std::shared_ptr<const LabeledImage>& image, const std::map<int32_t, int>& materialOfLabel,
    const std::string& inputName) {
  const auto& counts = image->labelCounts();
  std::vector<int32_t> missing;
  for (const auto& [label, material] : materialOfLabel)
    if (!counts.count(label) || label == 0) missing.push_back(label);
  if (!missing.empty()) {
    std::string list;
    for (int32_t l : missing) list += (list.empty() ? "" : ", ") + std::to_string(l);
    const std::string present = labelList(counts);
    if (missing.size() == materialOfLabel.size())
      throw InputError("no voxel of " + image->description() + " has a label of the 'materials' map (" + list +
                       "); the labels present are " + present + ": map those labels to materials");
    throw InputError(std::string("label") + (missing.size() > 1 ? "s " : " ") + list + " of the 'materials' map of input '" +
                     inputName + "' " + (missing.size() > 1 ? "do" : "does") + " not occur in " + image->description() +
                     " (labels present: " + present + "): fix the label or remove it from 'materials'");
  }
  std::vector<std::pair<std::shared_ptr<const ImageLabelRegion>, int>> regions;
  for (const auto& [label, material] : materialOfLabel)
    regions.emplace_back(
        std::make_shared<const ImageLabelRegion>(image, label, inputName + " label " + std::to_string(label)),
        material);
  return regions;
}

}  // namespace oraclemesh
