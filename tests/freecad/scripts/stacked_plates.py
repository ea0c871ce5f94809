"""Two steel plates 200 x 20 x 5 mm stacked (bottom z 0..5, top z 5..10), both fixed at x = 0,
100 N down on the top face (params["load"] "pull": 100 N up on the top plate's tip face),
joined as params["kind"] (optional params["friction"]) by makeMesh(interfaces=...), meshed by
OracleMesh (params["element_order"], default 2; cell size params["cell_size"], default 5;
params["fineness"], default the workbench's) and solved by CalculiX through FreeCAD's FEM workbench
(ccxtools: FreeCAD's own writer, with the workbench's tie / contact cards).

params["write_only"]: FreeCAD writes the input, nothing is solved. Returns the mean tip
deflection and what the written input holds: FreeCAD's element lines and
interface surfaces against the core's own INP of the same mesh (params["workdir"]/core.inp)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import fc_harness as h  # noqa: E402

# CalculiX's tet faces S1..S4, corners 0-based in the element line's order.
CCX_FACES = ((0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0))


def inp_blocks(path):
    """{'elements': {id: [nodes]}, 'surfaces': {NAME: {(element, 'Sk')}}, 'cards': [keyword
    lines]} of a CalculiX input (continuation lines joined)."""
    elements, surfaces, cards = {}, {}, []
    block, pending = None, []
    with open(path) as f:
        for raw in f:
            line = raw.strip()
            if not line or line.startswith("**"):
                continue
            if line.startswith("*"):
                cards.append(line.upper())
                key = line.upper().replace(" ", "")
                if key.startswith("*ELEMENT,"):
                    block = ("elements", None)
                elif key.startswith("*SURFACE,") and "TYPE=ELEMENT" in key:
                    name = [p.split("=")[1] for p in key.split(",") if p.startswith("NAME=")][0]
                    block = ("surface", name)
                    surfaces[name] = set()
                else:
                    block = None
                continue
            if block is None:
                continue
            if block[0] == "elements":
                pending += [v for v in line.split(",") if v.strip()]
                if line.endswith(","):
                    continue
                elements[int(pending[0])] = [int(v) for v in pending[1:]]
                pending = []
            else:
                element, face = [v.strip() for v in line.split(",")[:2]]
                surfaces[block[1]].add((int(element), face.upper()))
    return {"elements": elements, "surfaces": surfaces, "cards": cards}


def friction_lines(path):
    """The data line after each *FRICTION card."""
    with open(path) as f:
        lines = [line.strip() for line in f]
    return [lines[i + 1] for i, line in enumerate(lines) if line.upper().startswith("*FRICTION")]


def check(params):
    import FreeCAD
    import ObjectsFem
    from oraclemesh_fc import makeMesh

    workdir = params["workdir"]
    doc = FreeCAD.newDocument("StackedPlates")
    bottom = h.box(doc, "Bottom", 0, 0, 0, 200, 20, 5)
    top = h.box(doc, "Top", 0, 0, 5, 200, 20, 5)
    doc.recompute()
    analysis, solver = h.analysis_with_solver(doc)
    h.material(doc, analysis, "Steel", 210000, 0.3, [top, bottom])
    fixed = ObjectsFem.makeConstraintFixed(doc, "ConstraintFixed")
    fixed.References = [(top, h.face_where(top, "x", 0)), (bottom, h.face_where(bottom, "x", 0))]
    analysis.addObject(fixed)
    force = ObjectsFem.makeConstraintForce(doc, "ConstraintForce")
    pulled = params.get("load") == "pull"
    # Pressing: 100 N down on the top face. Pulling: 100 N up on the top plate's tip face.
    force.References = [(top, h.face_where(top, "x", 200) if pulled else h.face_where(top, "z", 10))]
    force.Force = 100.0
    force.Direction = (top, [h.edge_along(top, "z")])
    force.Reversed = False
    force.Reversed = (force.DirectionVector.z > 0) != pulled
    analysis.addObject(force)

    core_inp = os.path.join(workdir, "core.inp")
    pair = {"between": ["Top", "Bottom"], "kind": params["kind"]}
    if "friction" in params:
        pair["friction"] = params["friction"]
    settings = {"pairs": [pair]}
    size = params.get("cell_size", 5.0)
    mesh = makeMesh(doc, [top, bottom], analysis=analysis, cell_size=size, facet_size=size,
                    element_order=params.get("element_order", 2), seed=0, interfaces=settings,
                    fineness=params.get("fineness", "moderate"), output={"files": [core_inp]})
    facts = h.recompute_mesh(doc, mesh)
    if params.get("write_only"):  # FreeCAD's writer only: what the input holds
        from femtools import ccxtools
        if params.get("then_tied"):  # changed, not meshed again: the input follows the mesh
            mesh.Interfaces = '{"default": "tied"}'
        fea = ccxtools.FemToolsCcx(analysis, solver)
        fea.update_objects()
        fea.setup_working_dir(os.path.join(workdir, "ccx"))
        fea.write_inp_file()
        import json
        with open(fea.inp_file_name) as f:
            keywords = [line.split(",")[0].strip().upper() for line in f if line.startswith("*")]
        return {"friction_lines": friction_lines(fea.inp_file_name), "keywords": keywords,
                "report_interfaces": json.loads(mesh.Report)["interfaces"]}
    disp, inp = h.solve_displacements(analysis, solver, os.path.join(workdir, "ccx"))
    fm = mesh.FemMesh
    nodes = fm.Nodes
    tip = [n for n, p in nodes.items() if abs(p.x - 200) < 1e-6]
    on_top = [n for n in tip if nodes[n].z > 5 + 1e-6]
    below = [n for n in tip if nodes[n].z < 5 - 1e-6]

    written, core = inp_blocks(inp), inp_blocks(core_inp)

    def corner_sets(blocks, name):
        """The faces of a surface as sets of corner nodes (files may order an element's
        nodes differently: FreeCAD swaps the first two corners)."""
        faces = blocks["surfaces"].get(name.upper())
        if faces is None:
            return None
        return sorted(sorted(blocks["elements"][e][k] for k in CCX_FACES[int(s[1:]) - 1])
                      for e, s in faces)
    interface_names = [fm.getGroupName(g) for g in fm.Groups
                       if fm.getGroupElementType(g) == "Face"
                       and fm.getGroupName(g).startswith("Interface_")]
    import json
    report = json.loads(mesh.Report)
    mean = lambda ns: sum(disp[n][2] for n in ns) / len(ns)  # noqa: E731
    return {
        "tip_deflection": -mean(tip), "top_tip": -mean(on_top), "bottom_tip": -mean(below),
        "mesh": facts, "status": mesh.Status, "nodes": fm.NodeCount,
        "interfaces_property": mesh.Interfaces,
        "report_interfaces": report["interfaces"],
        "friction_lines": friction_lines(inp),
        "cards": [c for c in written["cards"]
                  if c.split(",")[0] in ("*TIE", "*CONTACT PAIR", "*SURFACE INTERACTION",
                                         "*SURFACE BEHAVIOR", "*FRICTION", "*STEP", "*STATIC")],
        "step_after_cards": [c.split(",")[0] for c in written["cards"]].index("*STEP")
        > max([i for i, c in enumerate(written["cards"])
               if c.split(",")[0] in ("*TIE", "*CONTACT PAIR")] or [-1]),
        # FreeCAD renumbers nothing: its elements have the core's ids and nodes.
        "elements_equal": {e: sorted(n) for e, n in written["elements"].items()}
        == {e: sorted(n) for e, n in core["elements"].items()},
        "elements": len(written["elements"]),
        "interface_groups": interface_names,
        # The surfaces the workbench wrote are the core's, face by face.
        "surfaces_equal": {name: corner_sets(written, name) == corner_sets(core, name)
                           for name in interface_names},
        "surfaces_written": sorted(n for n in written["surfaces"]),
        "surface_faces": {n: len(v) for n, v in written["surfaces"].items()},
    }


h.main(check)
