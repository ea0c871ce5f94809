"""Random byte changes and truncations of real model files through the CLI, the whole job: the
libFuzzer targets stop after loading, so what OpenCASCADE does to a damaged shape while it is
meshed (classification, sharp edges, tessellation) is found here.

    /usr/bin/python3 tests/fuzz/mutate_cli.py --tries 400 --seed 1818 --out /tmp/mutations MODEL.brep ...

Each try changes 1 to 3 characters (after the first 200 bytes) into a digit, '-', '.', 'e' or a
space (--digits-only: a digit of a real number into another, so that the file stays
well-formed and its geometry changes), or (one try in five, not with --digits-only) cuts the
file at a random point in its second half, and meshes it with the default job (element order
1) under --time-limit. Every try is a line of OUT/log.jsonl (exit code, seconds, last phase,
last message line); the mutated file and its job are kept when the try ends with a signal,
exit code 1 or later than the time limit plus the CLI's grace and SLACK_SECONDS (those are
findings). A summary by outcome is printed at the end.
Choose a time limit the unchanged models mesh within: otherwise exit 3 says nothing.

--reader-only runs the helper oraclemesh-shape-reader instead of the CLI (the load phase alone:
read, checks, sewing, tessellation, a probe of the classifier; several times as many tries an
hour) and names the phase a try stalled in from the helper's stack (where_stalled.py); a stall
is run again with four times the limit (a loaded machine makes big models slow) and kept,
stalled or slow, to be confirmed through the CLI; the helper's signals are only counted (the
CLI turns them into "OpenCASCADE crashed reading").
"""
import argparse
import collections
import json
import os
import random
import re
import subprocess
import time

from where_stalled import where_stalled

HERE = os.path.dirname(os.path.abspath(__file__))
CLI = os.path.join(os.environ.get("ORACLEMESH_BUILD_DIR", os.path.join(HERE, "..", "..", "build")), "oraclemesh")
SLACK_SECONDS = 5  # process start and a loaded machine, beyond the limit and the CLI's grace
PHASE = re.compile(r"\[oraclemesh\] ([a-z_ ]+?) \d+%")
REAL = re.compile(rb"-?\d+\.\d*(?:[eEdD][-+]?\d+)?")  # a real number in STEP, IGES or BREP text


def mutated(data, rng, digits_only=False):
    data = bytearray(data)
    if digits_only:  # the file stays well-formed, its geometry changes (not its references)
        places = [i for m in REAL.finditer(data, min(200, len(data) - 1)) for i in range(m.start(), m.end())
                  if chr(data[i]).isdigit()]
        changes = []
        for _ in range(rng.randint(1, 3)):
            position = rng.choice(places)
            new = rng.choice(b"0123456789")
            changes.append((position, chr(data[position]), chr(new)))
            data[position] = new
        return bytes(data), "changed %s" % changes
    if rng.random() < 0.2:
        cut = rng.randrange(len(data) // 2, len(data))
        return bytes(data[:cut]), "truncated at %d" % cut
    changes = []
    for _ in range(rng.randint(1, 3)):
        position = rng.randrange(min(200, len(data) - 1), len(data))
        new = rng.choice(b"0123456789-.e ")
        changes.append((position, chr(data[position]), chr(new)))
        data[position] = new
    return bytes(data), "changed %s" % changes


def outcome(code, message):
    if not isinstance(code, int) or code < 0:
        return "signal or no end"
    if code == 2:
        for part in ("did not finish reading", "did not finish working", "crashed reading", "has a tolerance",
                     "whose curve ends", "collapses", "not a readable", "non-finite", "not a finite",
                     "open shell", "holds no shape"):
            if part in message:
                return "exit 2: " + part
        return "exit 2: other"
    return "exit %d" % code


def reader_outcome(path, seconds):
    """The helper's outcome on `path` within `seconds`, and its message or the frames naming
    where it stalled."""
    result = where_stalled(path, seconds)
    if result[0] == "stalled":  # or slow on a loaded machine: a second chance, four times as long
        start = time.monotonic()
        again = where_stalled(path, 4 * seconds)
        if again[0] == "stalled":
            return "helper stalled: " + again[1], again[2][:12]
        return "helper slow: %s after %.0f s" % (outcome(again[1], again[2]), seconds + time.monotonic() - start), []
    code, message = result[1], result[2]
    return ("helper " + outcome(code, message) if code >= 0 else "helper signal %d" % -code), message[:400]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("models", nargs="+", help="STEP, IGES or BREP files to mutate")
    parser.add_argument("--tries", type=int, default=100)
    parser.add_argument("--seed", type=int, default=18)
    parser.add_argument("--time-limit", type=float, default=3)
    parser.add_argument("--out", required=True, help="folder for log.jsonl and the findings")
    parser.add_argument("--digits-only", action="store_true", help="change a digit of a real number only (see above)")
    parser.add_argument("--reader-only", action="store_true", help="run the helper, not the CLI (see above)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    models = {path: open(path, "rb").read() for path in args.models}
    rng = random.Random(args.seed)
    grace = min(30.0, max(2.0, 0.1 * args.time_limit))  # the CLI's (src/cli/HardDeadline.h)
    counts = collections.Counter()
    with open(os.path.join(args.out, "log.jsonl"), "a") as log:
        for i in range(args.tries):
            model = rng.choice(sorted(models))
            data, how = mutated(models[model], rng, args.digits_only)
            stem = os.path.join(args.out, "try%04d_%s" % (i, os.path.basename(model)))
            with open(stem, "wb") as f:
                f.write(data)
            with open(stem + ".json", "w") as f:
                json.dump({"inputs": [{"name": "m", "file": os.path.abspath(stem), "material": 1}],
                           "element_order": 1, "limits": {"time_limit": args.time_limit}}, f)
            start = time.monotonic()
            if args.reader_only:
                kind, detail = reader_outcome(stem, args.time_limit)
                counts[kind] += 1
                log.write(json.dumps({"try": i, "model": os.path.basename(model), "mutation": how,
                                      "seconds": round(time.monotonic() - start, 2), "outcome": kind,
                                      "stack" if "stalled" in kind else "message": detail}) + "\n")
                log.flush()
                if "stalled" not in kind and "slow" not in kind:  # the helper's signals are contained: counted
                    os.remove(stem)
                    os.remove(stem + ".json")
                continue
            try:
                run = subprocess.run([CLI, stem + ".json"], capture_output=True, text=True,
                                     timeout=args.time_limit + grace + 60)
                code, stderr = run.returncode, run.stderr
            except subprocess.TimeoutExpired as e:
                code, stderr = "no end", (e.stderr or b"").decode(errors="replace")
            seconds = time.monotonic() - start
            phases = PHASE.findall(stderr)
            message = stderr.strip().splitlines()[-1] if stderr.strip() else ""
            kind = outcome(code, message)
            counts[kind] += 1
            log.write(json.dumps({"try": i, "model": os.path.basename(model), "mutation": how, "exit": code,
                                  "seconds": round(seconds, 2), "phase": phases[-1] if phases else "",
                                  "outcome": kind, "message": message[:400]}) + "\n")
            log.flush()
            finding = kind in ("signal or no end", "exit 1") or seconds > args.time_limit + grace + SLACK_SECONDS
            if not finding:
                os.remove(stem)
                os.remove(stem + ".json")
    for kind, n in counts.most_common():
        print("%5d  %s" % (n, kind))


if __name__ == "__main__":
    main()
