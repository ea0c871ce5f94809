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
}




def test_bad_inputs_fail_cleanly(run_freecad):
    r = run_freecad("bad_inputs.py", timeout=900)["cases"]
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
    assert not problems, "\n".join(problems)
