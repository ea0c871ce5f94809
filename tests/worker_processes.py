"""The oraclemesh.worker processes a process has started (the Python tests and the FreeCAD
GUI test both check that a cancelled or crashed job leaves none behind)."""
import os


def live_worker_children(parent=None):
    """Pids of live (not zombie) oraclemesh.worker children of `parent` (default: this process)."""
    parent = os.getpid() if parent is None else parent
    pids = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                cmdline = f.read()
            with open("/proc/%s/stat" % pid) as f:
                fields = f.read().rsplit(")", 1)[1].split()  # after the command name
        except OSError:
            continue
        state, parent_pid = fields[0], int(fields[1])
        if b"oraclemesh.worker" in cmdline and parent_pid == parent and state != "Z":
            pids.append(int(pid))
    return pids
