#pragma once
// Conversions between the core's plain geometry (Geometry.h) and OpenCASCADE's points and
// vectors, for every layer that talks to OpenCASCADE (domain/brep, features, refine).
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <gp_XYZ.hxx>

#include "Geometry.h"

namespace oraclemesh {

inline Point3 toPoint3(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }
inline Point3 toPoint3(const gp_Vec& v) { return {v.X(), v.Y(), v.Z()}; }
inline Point3 toPoint3(const gp_XYZ& p) { return {p.X(), p.Y(), p.Z()}; }
inline gp_Pnt toGp(const Point3& p) { return gp_Pnt(p[0], p[1], p[2]); }

}  // namespace oraclemesh
