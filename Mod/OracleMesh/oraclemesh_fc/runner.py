"""Run a job through the core: console progress headless, a progress dialog in the GUI.

The core always runs in a child process (oraclemesh.run_isolated), so a crash of the native
code becomes an error message and FreeCAD keeps running. In the GUI a worker thread waits on
that process so the main window keeps painting; the main thread pumps Qt events and owns
every widget, the worker only writes the latest (phase, fraction) into a shared dict. Cancel
sets an event that ends the child process at once, also in phases that report no progress.
"""
import threading
import time

import FreeCAD


def import_core():
    """The core module, or a clear error telling how to make FreeCAD find it."""
    try:
        import oraclemesh
    except ImportError as e:
        raise ImportError(
            "the OracleMesh core module 'oraclemesh' cannot be imported (%s): build the project "
            "and run cmake/install-workbench.sh BUILD_DIR, which links BUILD_DIR/python/oraclemesh "
            "into FreeCAD's Mod/OracleMesh folder" % e) from None
    return oraclemesh


def run_job(job, label="OracleMesh"):
    if FreeCAD.GuiUp:
        return _run_with_dialog(job, label)
    return import_core().run_isolated(job, progress=_ConsoleProgress(label))


class _ConsoleProgress:
    """A message per phase, a log line every 25% inside a phase (keeps batch logs short)."""

    def __init__(self, label):
        self.label = label
        self.phase = None
        self.step = -1

    def __call__(self, phase, fraction):
        step = int(fraction * 4)
        if phase != self.phase:
            self.phase, self.step = phase, step
            FreeCAD.Console.PrintMessage("%s: %s\n" % (self.label, phase))
        elif step > self.step:
            self.step = step
            FreeCAD.Console.PrintLog("%s: %s %d%%\n" % (self.label, phase, int(fraction * 100)))
        return True


def _run_with_dialog(job, label):
    from PySide import QtCore, QtGui
    import FreeCADGui

    core = import_core()
    state = {"phase": "start", "fraction": 0.0, "result": None, "error": None}
    cancel = threading.Event()

    def progress(phase, fraction):  # worker thread: no Qt calls here
        state["phase"], state["fraction"] = phase, fraction
        return not cancel.is_set()

    def work():
        try:
            state["result"] = core.run_isolated(job, progress=progress, cancel=cancel)
        except BaseException as e:  # handed to the main thread, re-raised there
            state["error"] = e

    worker = threading.Thread(target=work, name="oraclemesh", daemon=True)
    dialog = QtGui.QProgressDialog("%s: meshing..." % label, "Cancel", 0, 1000,
                                   FreeCADGui.getMainWindow())
    dialog.setWindowTitle("OracleMesh")
    dialog.setWindowModality(QtCore.Qt.WindowModal)  # no edits of the document meanwhile
    dialog.setMinimumDuration(300)
    started = time.time()
    worker.start()
    try:
        while worker.is_alive():
            worker.join(0.05)
            if dialog.wasCanceled():
                cancel.set()
            dialog.setLabelText("%s: %s (%.0f s)" % (label, state["phase"], time.time() - started))
            dialog.setValue(int(1000 * min(max(state["fraction"], 0.0), 1.0)))
            QtGui.QApplication.processEvents()
    finally:
        dialog.reset()
        dialog.deleteLater()
    if state["error"] is not None:
        raise state["error"]
    return state["result"]
