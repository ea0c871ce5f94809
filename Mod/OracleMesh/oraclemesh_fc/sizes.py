"""The sizes the core will use where the job leaves them unset, so the task panel can show
what "automatic" means before meshing.

The rule is the core's (src/core/job/ResolvedCriteria.cpp, resolveCriteria): unset defaults
follow the bounding-box diagonal of the material inputs (cuts do not count), a material's
own entries are merged over the defaults. The GUI tests compare what the panel shows with
the criteria the core reports, so a change of the rule on one side fails there.
"""
import FreeCAD

from .job import MeshInputError, global_mesh, global_shape, is_mesh_feature

# Sizes from the geometry below the sizes above (the core's criteria.fineness,
# src/core/sizing/Fineness.h, whose unset value is "moderate"); "off" leaves the sizes above
# alone. The panel's automatic values are the caps the field stays under.
FINENESS_NAMES = ("off", "very coarse", "coarse", "moderate", "fine", "very fine")
DEFAULT_FINENESS = "moderate"

# cell_size = diagonal / CELL_SIZE_DIVISOR when unset.
CELL_SIZE_DIVISOR = 15.0
DEFAULT_RADIUS_EDGE_RATIO = 2.0
DEFAULT_FACET_ANGLE = 25.0


def model_diagonal(objs):
    """Diagonal of the box around the given input objects in global coordinates, as the core
    measures it (the exact geometry, not a tessellation); 0 when none has geometry."""
    box = FreeCAD.BoundBox()
    for obj in objs:
        try:
            if is_mesh_feature(obj):
                for p in global_mesh(obj)[0]:
                    box.add(FreeCAD.Vector(*p))
            else:
                # Without the display's tessellation, the box is the exact geometry's.
                box.add(global_shape(obj).copy(True, False).BoundBox)
        except MeshInputError:
            continue  # reported by the mesh object; it adds nothing to the box
    return box.DiagonalLength if box.isValid() else 0.0


def resolved_defaults(diagonal, given):
    """All six criteria of the job's defaults: those in given ({key: value}, set values
    only), the rest derived as the core derives them."""
    c = {}
    c["cell_size"] = given.get("cell_size", diagonal / CELL_SIZE_DIVISOR)
    c["facet_size"] = given.get("facet_size", c["cell_size"])
    c["facet_distance"] = given.get("facet_distance", c["facet_size"] / 10)
    c["cell_radius_edge_ratio"] = given.get("cell_radius_edge_ratio", DEFAULT_RADIUS_EDGE_RATIO)
    c["facet_angle"] = given.get("facet_angle", DEFAULT_FACET_ANGLE)
    c["edge_size"] = given.get("edge_size", c["facet_size"] / 2)
    return c


def resolved_material(defaults, given):
    """A material's criteria: its own entries over the resolved defaults (an unset entry is
    the default's value, not derived from the material's own cell size)."""
    return dict(defaults, **given)
