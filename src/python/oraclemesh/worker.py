"""Child-process side of oraclemesh.run_isolated: `python3 -m oraclemesh.worker JOB RESULT`.

Runs the job in its own process so that a crash of the native core (a segfault in CGAL or
OpenCASCADE) ends this process, not FreeCAD. Speaks to the parent through:
  stdout  one line per progress report: "progress <fraction> <phase>"
  RESULT  an .npz with the result arrays and the report (on success, exit 0)
  RESULT.error.json  {"type": "InputError", "message": ...} (on an oraclemesh.Error, exit 2)
"""
import json
import sys

import numpy as np

import oraclemesh


def main(job_path, result_path):
    def progress(phase, fraction):
        sys.stdout.write("progress %.6f %s\n" % (fraction, phase))
        sys.stdout.flush()

    try:
        result = oraclemesh.run(job_path, progress=progress)
    except oraclemesh.Error as e:
        with open(result_path + ".error.json", "w") as f:
            json.dump({"type": type(e).__name__, "message": str(e)}, f)
        return 2
    np.savez(result_path, report=np.array(json.dumps(result.report)),
             **{name: getattr(result, name) for name in oraclemesh.Result.ARRAYS})
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
