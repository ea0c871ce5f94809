"""Bad inputs through FreeCAD give a clear error (checked text) and change nothing."""


# case -> words the message must contain (lower case): what is wrong and which input.
EXPECTED = {
    "no_inputs": ["no inputs", "inputs"],
    "face_only": ["faceonly", "solid"],
    "open_shell": ["openshell"],
    "only_cuts": ["goodbox", "cuts", "nothing"],
    "negative_size": ["inputsizes['goodbox']", "positive"],
    "nan_size": ["inputsizes['goodbox']", "positive"],
    "too_many_vertices": ["max_vertices"],
    "not_a_shape": ["justagroup", "no shape"],
    "unknown_size_key": ["nope", "inputsizes"],
    "listed_twice": ["goodbox", "twice"],
    "interface_unknown_part": ["interfaces of", "'nope' is no part", "'goodbox'"],
    "interface_bad_kind": ["interfaces of", "default = 'glued'", "bonded, tied, contact"],
    "interface_not_json": ["interfaces of", "no json", "empty for all bonded"],
    "fails_its_check": ["'pin'", "less volume", "element_order 2", "inputsizes['pin']",
                        "set the mesh object's checks to warn"],
}
# makeMesh(interfaces=...) case -> words of its refusal (lower case): the key and the fix.
REFUSED = {
    "kind": ["interfaces=...).pairs[0].kind = 'glued'", "bonded, tied, contact, separate"],
    "friction": ["pairs[0].friction", "contact' only"],
    "part": ["pairs[0].between[1] = 'nope' is no part", "'goodbox', 'other'"],
    "key": ["unknown key(s) 'mu'", "friction"],
}




def test_bad_inputs_fail_cleanly(run_freecad):
    r_all = run_freecad("bad_inputs.py", timeout=900)
    r = r_all["cases"]
    problems = []
    for case, words in EXPECTED.items():
        c = r[case]
        text = c["status"].lower()
        print("%-18s %s" % (case, c["status"]))
        if c["valid"] or "Invalid" not in c["state"]:
            problems.append("%s: the object is not marked as failed (%s)" % (case, c["state"]))
        if not c["mesh_kept"] or not c["objects_kept"]:
            problems.append("%s: the previous mesh or the document changed" % case)
        missing = [w for w in words if w not in text]
        if missing:
            problems.append("%s: message lacks %s: %s" % (case, missing, c["status"]))
        if "the previous mesh is kept" not in text:
            problems.append("%s: the message does not say the mesh is kept" % case)
    # Linking an object twice is said as soon as it is linked, not as a traceback.
    assert any("listed twice" in k for k in r["listed_twice"]["kinds"]), r["listed_twice"]
    assert r["recovered"], "the mesh did not recompute after the inputs were fixed"
    kept = r["kept_with_warn"]
    print("kept with warn:", kept["printed"])
    assert kept["valid"] and kept["volumes"] > 0
    short = [w for w in kept["warnings"] if "'pin'" in w.lower() and "less volume" in w]
    assert short and all("InputSizes['Pin']" in w and "criteria.materials" not in w for w in short), kept
    assert any(p.startswith("OracleMesh '") and short[0] in p for p in kept["printed"]), kept
    for case, words in REFUSED.items():
        c = r_all["refused"][case]
        print("makeMesh refused %-9s %s" % (case, c["message"]))
        text = (c["message"] or "").lower()
        missing = [w for w in words if w not in text]
        if c["message"] is None or missing or not c["objects_kept"]:
            problems.append("makeMesh(interfaces=%s): %s, lacks %s, objects kept %s"
                            % (case, c["message"], missing, c["objects_kept"]))
    assert not problems, "\n".join(problems)
