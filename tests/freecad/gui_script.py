"""Helpers for the scripts that tests/freecad runs inside the FreeCAD GUI (gui_session.py
starts them). A script does:
    import os, sys; sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    from gui_script import main, pump
    def check(out): ...  # fills the dict out
    main(check)

Unlike fc_harness (freecadcmd), the workbench is the installed one, as a user has it."""
import json
import os
import time
import traceback


def pump(seconds=0.2):
    """Let Qt process events for a while (dialogs open, views repaint)."""
    from PySide import QtGui
    end = time.time() + seconds
    while time.time() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.01)


def main(check):
    """Run check(out) and write out (or the traceback) as JSON to $OMFC_RESULT, then leave
    FreeCAD at once (nothing to save, no dialog asking)."""
    result = {"ok": True}
    try:
        check(result)
    except BaseException:
        result["ok"] = False
        result["traceback"] = traceback.format_exc()
    with open(os.environ["OMFC_RESULT"], "w") as f:
        json.dump(result, f, indent=1, default=str)
    os._exit(0)


def step(text):
    """Append a line to the trail of steps ($OMFC_RESULT.steps): a GUI crash shows where."""
    with open(os.environ["OMFC_RESULT"] + ".steps", "a") as f:
        f.write("%.1f %s\n" % (time.time(), text))
