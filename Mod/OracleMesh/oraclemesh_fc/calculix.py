"""Solve an analysis with CalculiX headless (FreeCAD's ccxtools), for macros and batch runs.

The FEM workbench's own solver task panel does the same in the GUI; this is the scripted
path the demo and the tests use.
"""
import os


def run_calculix(analysis, solver, workdir):
    """Write the .inp, run ccx, load the results. Returns (result object, inp path); the
    result is the step's end (a nonlinear step, e.g. with contact, loads one result object
    per increment, in time order).

    Raises RuntimeError with CalculiX's last output when any step fails."""
    from femtools import ccxtools

    os.makedirs(workdir, exist_ok=True)
    fea = ccxtools.FemToolsCcx(analysis, solver)
    fea.update_objects()
    fea.setup_working_dir(workdir)
    message = fea.check_prerequisites()
    if message:
        raise RuntimeError("CalculiX prerequisites are not met: " + message)
    fea.write_inp_file()
    if not fea.inp_file_name:
        raise RuntimeError("FreeCAD could not write the CalculiX input file in " + workdir)
    code = fea.ccx_run()
    if code != 0:
        raise RuntimeError("CalculiX failed (exit %r) in %s:\n%s"
                           % (code, workdir, (fea.ccx_stdout or "")[-3000:]))
    fea.load_results()
    results = [o for o in analysis.Group if o.isDerivedFrom("Fem::FemResultObject")]
    if not results:
        raise RuntimeError("no CalculiX results were loaded from " + workdir)
    return results[-1], fea.inp_file_name
