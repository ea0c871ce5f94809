#pragma once
// A local mesh size over space, from size samples: the size at p is the smallest
// h_i + grading * |p - x_i| over the samples (x_i, h_i), capped. The cone per sample makes the
// field Lipschitz with constant `grading`, so sizes grow away from small features instead of
// jumping (Netgen's grading, Gmsh's size gradation). "Size" has the unit of the job's
// cell_size and facet_size (a Delaunay ball radius); job/ResolvedCriteria derives the other
// criteria from it as it does from a given size.
#include <memory>
#include <string>
#include <vector>

#include "Geometry.h"

namespace oraclemesh {

// Why a sample asks for its size: the report counts samples per reason.
enum class SizeReason { Curvature, ShortEdge, Thickness, Gap };
constexpr int kSizeReasonCount = 4;
const char* sizeReasonName(SizeReason reason);

struct SizeSample {
  Point3 point{};
  double size = 0;
  SizeReason reason = SizeReason::Curvature;
};

class SizeField {
 public:
  // Samples with a size at or above `cap` are dropped (the cap holds everywhere anyway); sizes
  // below `floor` are raised to it. Throws InputError for a grading that is not positive.
  // `thinning` > 0 drops the samples the others give within that relative tolerance
  // (sizing/SampleThinning.h): the field is then at most (1 + thinning) times the one of all
  // samples, and still exactly the graded minimum over the samples it kept.
  SizeField(std::vector<SizeSample> samples, double grading, double cap, double floor, double thinning = 0);
  ~SizeField();
  SizeField(const SizeField&) = delete;
  SizeField& operator=(const SizeField&) = delete;

  // The size at p: min(cap, min_i size_i + grading |p - x_i|) over the kept samples, exactly
  // (sizing/ConeTree.h). Thread-safe (const, no cache).
  double at(const Point3& p) const;

  double grading() const;
  double cap() const;
  double floor() const;
  size_t sampleCount() const;  // kept (after thinning)
  size_t samplesTaken() const;  // under the cap, before thinning
  size_t sampleCount(SizeReason reason) const;
  // The smallest sample size and where it is, for the report and for messages.
  double smallestSize() const;
  Point3 smallestAt() const;
  SizeReason smallestReason() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace oraclemesh
