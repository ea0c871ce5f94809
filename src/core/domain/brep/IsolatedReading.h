#pragma once
// B-rep inputs read in a helper process (internal to domain/brep; the entry points are
// BrepSolid::loadFileIsolated and loadBrepTextIsolated). OpenCASCADE's readers, sewing and
// tessellation run on whatever bytes the user gives, and on damaged files they crash
// (segfaults in the STEP reader) or loop (BREP reader, BRepMesh). The helper,
// `oraclemesh-shape-reader`, does all of BrepSolid::load on the file and writes the loaded
// solids back as binary BREP (exact doubles), tessellation included; the caller waits within
// the job's time limit and cancel, kills the helper when they end the wait, turns a signal
// into an InputError naming the file, and loads the clean solids with the tessellation they
// carry (BrepSolid::Tessellation::Reuse: no OpenCASCADE meshing outside the helper). posix_spawn, not fork: the caller may be a multi-threaded Python process.
//
// The helper is found beside the executable or shared library that holds the core (the CLI,
// the Python module _core, a test program), then in ../libexec/oraclemesh from there, then
// beside /proc/self/exe; ORACLEMESH_SHAPE_READER names it explicitly.

namespace oraclemesh {

// main() of oraclemesh-shape-reader:
//   oraclemesh-shape-reader --file PATH | --text FILE  OUTDIR NAME separate|together PARENT_PID
// writes OUTDIR/solids.bin (binary BREP) and OUTDIR/warnings.txt (one warning a line), exit 0; or
// OUTDIR/error.txt, exit 2 (an InputError's message) or 3 (any other failure).
int shapeReaderMain(int argc, char** argv);

}  // namespace oraclemesh
