"""PNG plots of a batch: tetrahedra and minimum dihedral angle per case, one series per group.

Drawn with matplotlib's object interface on the Agg canvas, so that no pyplot state or GUI
backend of the calling program (FreeCAD) is touched.
"""
import os

PLOTS = (("tets", "tetrahedra", "tets.png"),
         ("min_dihedral_deg", "minimum dihedral angle (degrees)", "min_dihedral.png"))


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def write_plots(out, rows, group_by=None, x=None):
    """Writes OUT/tets.png and OUT/min_dihedral.png; returns their paths (none without
    matplotlib or without a succeeded case)."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from matplotlib.ticker import MaxNLocator
    except ImportError:
        return []
    ok = [r for r in rows if r["status"] == "ok"]
    if not ok:
        return []
    groups = {}
    for row in ok:
        groups.setdefault(str(row.get(group_by, "")) if group_by else "all", []).append(row)
    numeric_x = x is not None and all(_is_number(r.get(x)) for r in ok)
    paths = []
    for metric, label, name in PLOTS:
        figure = Figure(figsize=(8, 4.5))
        FigureCanvasAgg(figure)
        axes = figure.add_subplot()
        for group, members in groups.items():
            xs = [r[x] for r in members] if numeric_x else list(range(1, len(members) + 1))
            ys = [r.get(metric) if _is_number(r.get(metric)) else float("nan") for r in members]
            axes.plot(xs, ys, marker="o", markersize=4, linestyle="-", linewidth=0.6, label=group)
        failed = len(rows) - len(ok)
        axes.set_xlabel(x if numeric_x else "case (in order, per group)")
        axes.set_ylabel(label)
        axes.set_title("%s per %s%s" % (label, x if numeric_x else "case",
                                        ", %d failed case(s) not shown" % failed if failed else ""))
        if not numeric_x or all(isinstance(r[x], int) for r in ok):
            axes.xaxis.set_major_locator(MaxNLocator(integer=True))
        axes.grid(True, alpha=0.3)
        if group_by:
            axes.legend(title=group_by)
        figure.tight_layout()
        path = os.path.join(out, name)
        figure.savefig(path, dpi=100)
        paths.append(path)
    return paths
