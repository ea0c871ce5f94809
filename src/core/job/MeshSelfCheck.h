#pragma once
// The finished mesh checked against the inputs it was made from, by figures that do not come
// from the mesh: each material's volume against the volume the hierarchical oracle gives it,
// and each part's tetrahedra against splitting into pieces. A mesh whose elements are too
// large for a part can lose a fifth of its volume while every element is fine; only such a
// comparison shows it.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "Error.h"
#include "domain/HierarchicalOracle.h"
#include "job/JoinedParts.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

// One material's figures (report.self_check.materials."<id>").
struct MaterialVolumeCheck {
  std::string parts;         // the names of the oracle entries of this material, for messages
  double input_volume = 0;   // what the oracle gives the material: the entries' volumes less overlaps
  double error_bar = 0;      // of input_volume: 0 when it is exact, else 3 sigma of the ray estimate
  double mesh_volume = 0;    // as the solver sees it (curved for tet10)
  double deviation = 0;      // (mesh - input) / input
  int64_t components = 0;    // face-connected pieces of the material's tetrahedra
  int64_t max_components = -1;  // how many pieces it may have; -1 when not known (a cut or overlap may split it)
};

// A mesh that failed the check, under "checks": "error": its sizes are too coarse for the model.
class MeshCheckError : public InputError {
 public:
  using InputError::InputError;
};

struct MeshSelfCheck {
  double volume_tolerance = 0.01;  // relative; the error bar widens it where it is larger
  std::map<int, MaterialVolumeCheck> materials;
  // A vertex between two parts this far from either is across a gap (model units).
  double contact_tolerance = 0;
  std::vector<JoinedAcrossGap> interface_gaps;  // every pair of parts sharing mesh faces
  std::vector<JoinedAcrossGap> joined;  // of those, the pairs the mesh joins where they do not touch
  std::vector<std::string> problems;  // one sentence each: the part, the figure, the fix
};

// Compares `mesh` with `oracle`. Volumes of oracle entries are their own exact volumes
// (Source::volume; OpenCASCADE's for B-reps); where a higher-priority entry or a cut may
// overlap one, the overlap is measured along jittered rays through the boxes they share, cut
// exactly by the sources' crossings, and subtracted, with its error bar. `volume_per_material` is the mesh's (QualityReport).
// Parts joined across a gap (measureInterfaceGaps with `contact_tolerance`; 0 = 1e-6 of
// the diagonal; the wedges the sizing bonded, `bonded_wedges`, may be null) are a problem when
// more than volume_tolerance of their interface is joined.
MeshSelfCheck checkMeshAgainstInputs(const TetMesh& mesh, const HierarchicalOracle& oracle,
                                     const std::map<int, double>& volume_per_material,
                                     double contact_tolerance = 0,
                                     const std::vector<double>& distance_kept_off_cad = {},
                                     const BondedWedges* bonded_wedges = nullptr);

}  // namespace oraclemesh
