"""Helpers of the scripts that run inside the FreeCAD GUI (scripts/gui_*.py): the trail of
steps next to the result file (a GUI crash shows where it happened), and pumping Qt events
so the GUI catches up."""
import os
import time


def step(text):
    with open(os.environ["OMFC_RESULT"] + ".steps", "a") as f:
        f.write("%.1f %s\n" % (time.time(), text))


def pump(seconds=0.2):
    from PySide import QtGui
    end = time.time() + seconds
    while time.time() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.01)
