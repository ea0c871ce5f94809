#pragma once
// The CalculiX definitions that join the two sides of a split interface (issue 19): a *TIE for
// tied pairs, a surface-to-surface *CONTACT PAIR for contact pairs, with the choice of master
// and slave side and the numbers CalculiX needs, made once here for the INP and the report.
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/InterfaceKinds.h"
#include "mesh/Surfaces.h"
#include "mesh/TetMesh.h"

namespace oraclemesh {

struct InterfaceConstraint {
  int material = 0, other_material = 0;  // the pair, smaller id first
  InterfaceBehaviour behaviour;          // tied or contact
  // CalculiX projects the slave side's nodes onto the master side's faces. Master: the part
  // the job names (interfaces.pairs[i].master), else the coarser side, i.e. the one whose
  // tets at the interface have the larger mean volume (CalculiX wants the slave mesh at least
  // as fine; the faces themselves are the same triangles on both sides after the split, so
  // the tets behind them decide), the smaller material id when both are equal. The mesher
  // does not know the parts' stiffness; to make the stiffer part the master, name it.
  int master_material = 0, slave_material = 0;
  std::string master, slave;  // surface names (Interface_<master>_<slave>, Interface_<slave>_<master>)
  std::string name;           // Tie_<a>_<b> or Contact_<a>_<b> (a, b: the pair's parts by id)
  // Tied: how far a slave node may be from the master faces and still be tied: 1 % of the
  // shortest edge of the interface faces. The copies sit exactly where their originals are,
  // so only rounding separates them; an element-size tolerance could also catch nodes of
  // faces across a thin gap or at a sharp fold of the interface.
  double position_tolerance = 0;
  // Tied: slave face nodes that the master part's tets use too (kept joined through a part
  // bonded to both, InterfaceSplitStats::kept_joined) are not tied: CalculiX 2.20 stops on a
  // node tied to itself ("*ERROR in cascade: zero coefficient on the dependent term"). When
  // there are any, the tie's slave side is the node surface slave_nodes_name (an NSET of the
  // same name) over the other slave face nodes, slave_nodes (0-based, sorted); else both are
  // empty and the slave faces serve.
  std::vector<int64_t> slave_nodes;
  std::string slave_nodes_name;
  // Contact: the slope of CalculiX' linear pressure-overclosure law. The job's
  // (interfaces.pairs[i].contact_stiffness, else interfaces.contact_stiffness) if it gives one,
  // else 2.5 E / h with E = 210000 (steel in N and mm) and h the mean edge length of the
  // interface faces. HARD contact did not converge in CalculiX 2.20 once the surfaces open (two
  // plates pulled apart: 6 cut-backs of 60 iterations each); this slope did (1e5 N/mm^3 for
  // 5 mm faces). The mesher does not know the material: for another one give the slope.
  double contact_stiffness = 0;
  bool contact_stiffness_given = false;  // from the job, not the steel default
};

// One per pair that is tied or in contact and has faces on both sides in `surfaces`
// (meshSurfaces(mesh, plan) before the split), in the order of the pairs' ids.
std::vector<InterfaceConstraint> interfaceConstraints(const TetMesh& mesh, const std::vector<MeshSurface>& surfaces,
                                                      const MaterialNames& names, const InterfacePlan& plan);

// The constraints as CalculiX model-definition cards (no *STEP: they go with the mesh,
// before the user's step), one "**" comment line before each.
std::string calculixInterfaceCards(const std::vector<InterfaceConstraint>& constraints);

}  // namespace oraclemesh
