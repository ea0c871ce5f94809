// oraclemesh-shape-reader: the helper process in which OpenCASCADE reads B-rep inputs, so that
// its crash or hang on a damaged file cannot end the mesher (domain/brep/IsolatedReading.h).
#include "domain/brep/IsolatedReading.h"

int main(int argc, char** argv) { return oraclemesh::shapeReaderMain(argc, argv); }
