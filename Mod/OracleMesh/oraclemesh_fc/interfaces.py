"""Interface settings of a mesh object: how each pair of touching parts is joined (issue 19).

The setting is the job's `interfaces` value (src/README.md, "Interfaces"):
    {"default": "bonded", "pairs": [{"between": ["top", "bottom"], "kind": "contact",
                                      "friction": 0.2, "master": "top"}]}
with parts named as the report names them (the workbench's part labels: an object's Label,
or the label of one solid of a compound). The mesh object keeps it as JSON text in its
`Interfaces` property (empty = every pair bonded), so it survives save and reopen.

Checked here before anything is stored, so a macro's typo fails in makeMesh with the key and
the fix; whether the named parts exist is known only with the parts (`check_part_names`).
No FreeCAD import: the panel and the job builder share it.
"""
import json
import math

KINDS = ("bonded", "tied", "contact", "separate")
KIND_TIPS = {
    "bonded": "shared nodes: one conformal mesh (the parts are glued)",
    "tied": "own nodes on each side, tied by CalculiX (*TIE): glued, but meshed apart",
    "contact": "own nodes, a CalculiX contact pair: pressed together they carry load, pulled "
               "apart they separate (frictionless unless a friction is set)",
    "separate": "own nodes, nothing between them: a free gap the mesh must not bridge",
}
PAIR_KEYS = ("between", "kind", "friction", "master")
FORM = ('{"default": "bonded", "pairs": [{"between": ["part a", "part b"], "kind": "contact"}]}'
        ' with kinds %s' % ", ".join(KINDS))


class InterfaceSettingsError(ValueError):
    """A bad interfaces setting; the text names the key and the fix."""


def part_name(value):
    """A part as the settings name it: text, or a FreeCAD object (its Label)."""
    label = getattr(value, "Label", None)
    return label if isinstance(label, str) else value


def _kind(value, where):
    if value not in KINDS:
        raise InterfaceSettingsError("%s = %r is not an interface kind: use %s"
                                     % (where, value, ", ".join(KINDS)))
    return value


def normalized(settings, where="interfaces"):
    """The settings as plain JSON-able data, checked; None or {} gives {} (all bonded).

    Raises InterfaceSettingsError naming the offending key (`where`.pairs[i].kind, ...)."""
    if settings is None:
        return {}
    if not isinstance(settings, dict):
        raise InterfaceSettingsError("%s must be a dict like %s, got %r" % (where, FORM, settings))
    unknown = sorted(set(settings) - {"default", "pairs"})
    if unknown:
        raise InterfaceSettingsError("%s has unknown key(s) %s: use 'default' and 'pairs', as in %s"
                                     % (where, ", ".join(map(repr, unknown)), FORM))
    out = {}
    if "default" in settings:
        out["default"] = _kind(settings["default"], where + ".default")
    pairs = settings.get("pairs", [])
    if not isinstance(pairs, (list, tuple)):
        raise InterfaceSettingsError("%s.pairs must be a list of pairs, as in %s" % (where, FORM))
    seen = {}
    for i, pair in enumerate(pairs):
        at = "%s.pairs[%d]" % (where, i)
        if not isinstance(pair, dict):
            raise InterfaceSettingsError("%s must be a dict like %s" % (at, FORM))
        unknown = sorted(set(pair) - set(PAIR_KEYS))
        if unknown:
            raise InterfaceSettingsError("%s has unknown key(s) %s: use %s"
                                         % (at, ", ".join(map(repr, unknown)), ", ".join(PAIR_KEYS)))
        between = pair.get("between")
        if not isinstance(between, (list, tuple)) or len(between) != 2:
            raise InterfaceSettingsError("%s.between must name two parts, e.g. ['Pin', 'Plate'] "
                                         "(as the report's interfaces name them), got %r"
                                         % (at, between))
        between = [part_name(p) for p in between]
        if not all(isinstance(p, str) and p for p in between):
            raise InterfaceSettingsError("%s.between must name two parts by their labels (text "
                                         "or objects), got %r" % (at, between))
        if between[0] == between[1]:
            raise InterfaceSettingsError("%s.between names '%s' twice: an interface is between "
                                         "two different parts" % (at, between[0]))
        key = frozenset(between)
        if key in seen:
            raise InterfaceSettingsError("%s is the pair of %s.pairs[%d] again: give each pair once"
                                         % (at, where, seen[key]))
        seen[key] = i
        if "kind" not in pair:
            raise InterfaceSettingsError("%s has no 'kind': use %s" % (at, ", ".join(KINDS)))
        entry = {"between": between, "kind": _kind(pair["kind"], at + ".kind")}
        if "friction" in pair:
            friction = pair["friction"]
            if entry["kind"] != "contact":
                raise InterfaceSettingsError("%s.friction belongs to kind 'contact' only (this pair "
                                             "is '%s'): remove it or make the pair a contact"
                                             % (at, entry["kind"]))
            if isinstance(friction, bool) or not isinstance(friction, (int, float)) \
                    or not math.isfinite(friction) or friction < 0:
                raise InterfaceSettingsError("%s.friction = %r: give a Coulomb friction coefficient "
                                             ">= 0 (0 = frictionless)" % (at, friction))
            entry["friction"] = float(friction)
        if "master" in pair:
            if entry["kind"] not in ("tied", "contact"):
                raise InterfaceSettingsError("%s.master applies to kinds 'tied' and 'contact' only: "
                                             "remove it" % at)
            master = part_name(pair["master"])
            if master not in between:
                raise InterfaceSettingsError("%s.master = %r is not one of the pair's parts '%s' and "
                                             "'%s'" % (at, master, between[0], between[1]))
            entry["master"] = master
        out.setdefault("pairs", []).append(entry)
    return out


def to_text(settings):
    """The `Interfaces` property text of checked settings ('' = all bonded)."""
    return json.dumps(settings, sort_keys=True) if settings else ""


def from_text(text, where):
    """Checked settings from an `Interfaces` property text; `where` names the property."""
    if not str(text or "").strip():
        return {}
    try:
        value = json.loads(text)
    except ValueError as e:
        raise InterfaceSettingsError("%s is no JSON (%s): give it as %s, or empty for all bonded"
                                     % (where, e, FORM)) from None
    return normalized(value, where)


def check_part_names(settings, parts, where):
    """Every part a setting names is one of `parts` (the labels of the material parts)."""
    known = list(parts)
    for i, pair in enumerate(settings.get("pairs", [])):
        for k, name in enumerate(pair["between"]):
            if name not in known:
                raise InterfaceSettingsError(
                    "%s.pairs[%d].between[%d] = '%s' is no part of the mesh: the parts are %s "
                    "(name them by their labels, as the report's interfaces do)"
                    % (where, i, k, name, ", ".join("'%s'" % p for p in known)))


def default_kind(settings):
    return settings.get("default", "bonded")


def kind_between(settings, a, b):
    """The kind the settings give the pair (a, b)."""
    for pair in settings.get("pairs", []):
        if set(pair["between"]) == {a, b}:
            return pair["kind"]
    return default_kind(settings)


def with_kinds(settings, default, kinds):
    """New settings with this default and kinds {(a, b): kind} (the task panel's table).

    A pair whose kind is the default and that has no friction or master is left out; a
    pair's friction stays while it is a contact, its master while it is tied or contact."""
    old = {frozenset(p["between"]): p for p in settings.get("pairs", [])}
    pairs = []
    for between, kind in kinds.items():
        entry = dict(old.pop(frozenset(between), {"between": list(between)}))
        entry["kind"] = kind
        if kind != "contact":
            entry.pop("friction", None)
        if kind not in ("tied", "contact"):
            entry.pop("master", None)
        if kind != default or "friction" in entry or "master" in entry:
            pairs.append(entry)
    pairs += list(old.values())  # pairs the last mesh did not find stay as they were
    out = {"default": default} if default != "bonded" else {}
    if pairs:
        out["pairs"] = pairs
    return normalized(out)


def with_stiffer_masters(settings, moduli, touching):
    """The settings for the job: every tied or contact pair without a master gets the part of
    the larger Young's modulus as master (moduli {part: E}; parts of equal or unknown E are
    left to the core, which takes the coarser side). The pairs are those listed, and those of
    `touching` [(a, b)] (the last mesh's interfaces) that the default makes tied or contact."""
    out = {k: v for k, v in settings.items() if k != "pairs"}
    pairs = [dict(p) for p in settings.get("pairs", [])]
    listed = {frozenset(p["between"]) for p in pairs}
    if default_kind(settings) in ("tied", "contact"):
        pairs += [{"between": [a, b], "kind": default_kind(settings)} for a, b in touching
                  if frozenset((a, b)) not in listed]
    for p in pairs:
        a, b = p["between"]
        if p["kind"] in ("tied", "contact") and "master" not in p \
                and moduli.get(a) is not None and moduli.get(b) is not None \
                and moduli[a] != moduli[b]:
            p["master"] = a if moduli[a] > moduli[b] else b
    if pairs:
        out["pairs"] = pairs
    return out


def found_pairs(report):
    """[(part a, part b, area, triangles, area beyond the contact tolerance)] of the interfaces
    in a mesh report (dict)."""
    return [(e["parts"][0], e["parts"][1], float(e.get("area", 0.0)), int(e.get("triangles", 0)),
             float(e.get("beyond_contact_area", 0.0)))
            for e in report.get("interfaces", []) if len(e.get("parts", ())) == 2]


def pair_tip(a, b, area, triangles, beyond):
    """What the panel's row of a found pair says of it. The part beyond the contact tolerance
    is where the CAD's faces do not touch (a wedge beside a tangent contact, a contact's edge
    the mesh follows by a chord) but the mesh made interface: split for tied or contact, its
    two sides start closed there."""
    tip = "'%s' and '%s': %.6g mm^2, %d triangles in the last mesh" % (a, b, area, triangles)
    if beyond > 0:
        tip += ("; %.3g mm^2 of it where the parts are farther apart than the contact tolerance "
                "(beside a tangent contact or along the contact's edge), which tied or contact "
                "start closed" % beyond)
    return tip


def last_report(mesh_obj):
    """The mesh object's last report as a dict ({} before the first mesh or if unreadable)."""
    try:
        return json.loads(mesh_obj.Report) if mesh_obj.Report else {}
    except ValueError:
        return {}
