# OracleMesh workbench, application part (runs at every FreeCAD start, also headless).
# Nothing to register: the mesh object is created by oraclemesh_fc.makeMesh, and FreeCAD puts
# this folder on sys.path so `import oraclemesh_fc` (and the linked core `oraclemesh`) work
# in macros and freecadcmd scripts.
