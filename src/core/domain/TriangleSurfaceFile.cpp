#include "domain/TriangleSurfaceFile.h"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "Error.h"

namespace oraclemesh {

namespace {

using KPoint = CGAL::Simple_cartesian<double>::Point_3;

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool wholeNumber(const std::string& text, uint64_t& out) {
  if (text.empty() || text.size() > 18 || !std::all_of(text.begin(), text.end(), ::isdigit)) return false;
  out = std::stoull(text);
  return true;
}

// OFF is read here, not by CGAL: CGAL's OFF scanner sizes its arrays from the header and
// each face's corner count before reading them, and reads colours past the numbers a line
// has (found by tests/fuzz). ASCII only; the keyword may carry ST, C and N (texture, colour,
// normal data after the coordinates, ignored); x y z are the first numbers of a vertex line.
TriangleSoup readOff(const std::string& path, uintmax_t fileSize, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  size_t lineNumber = 0;
  std::string line;
  auto fail = [&](const std::string& problem) {
    throw InputError(what + " " + problem + " (line " + std::to_string(lineNumber) +
                     "): export it again (as ASCII OFF or STL)");
  };
  std::istringstream words;
  // The next line with data, comment cut off, into `words`; false at the end of the file.
  auto nextLine = [&] {
    while (std::getline(in, line)) {
      ++lineNumber;
      const std::string data = line.substr(0, line.find('#'));
      if (data.find_first_not_of(" \t\r") == std::string::npos) continue;
      words.clear();
      words.str(data);
      return true;
    }
    return false;
  };
  std::string keyword, word;
  if (!nextLine() || !(words >> keyword)) fail("has no OFF header");
  static const std::set<std::string> keywords{"OFF", "COFF", "NOFF", "CNOFF", "STOFF", "STCOFF", "STNOFF", "STCNOFF"};
  if (!keywords.count(keyword))
    fail("does not start with 'OFF' (or COFF, NOFF, STOFF...) but with '" + keyword.substr(0, 20) +
         "'; homogeneous (4OFF) and n-dimensional (nOFF) files are not read");
  std::vector<std::string> counts;
  while (counts.size() < 3 && (words >> word || (nextLine() && words >> word))) {
    if (counts.empty() && word == "BINARY") fail("is a binary OFF file, which is not read");
    counts.push_back(word);
  }
  uint64_t vertices = 0, faces = 0, edges = 0;
  if (counts.size() < 3 || !wholeNumber(counts[0], vertices) || !wholeNumber(counts[1], faces) ||
      !wholeNumber(counts[2], edges))
    fail("has no vertex, face and edge counts after '" + keyword + "'");
  // Every vertex line takes at least 6 bytes ("0 0 0\n"), every face line 8.
  if (6 * vertices + 8 * faces > fileSize + 16)
    fail("declares " + std::to_string(vertices) + " vertices and " + std::to_string(faces) + " faces, more than its " +
         std::to_string(fileSize) + " bytes can hold (truncated?)");
  TriangleSoup soup;
  soup.points.reserve(vertices);
  for (uint64_t v = 0; v < vertices; ++v) {
    Point3 p{};
    if (!nextLine() || !(words >> p[0] >> p[1] >> p[2]))
      fail("ends or has no x y z numbers at vertex " + std::to_string(v + 1) + " of " + std::to_string(vertices));
    soup.points.push_back(p);
  }
  soup.triangles.reserve(faces);
  for (uint64_t f = 0; f < faces; ++f) {
    uint64_t corners = 0;
    if (!nextLine() || !(words >> word) || !wholeNumber(word, corners))
      fail("ends or has no corner count at face " + std::to_string(f + 1) + " of " + std::to_string(faces));
    if (corners != 3)
      throw InputError(what + " has a face with " + word +
                       " corners: only triangles are read; triangulate the surface when exporting it");
    std::array<int64_t, 3> t{};
    for (int c = 0; c < 3; ++c) {
      uint64_t index = 0;
      if (!(words >> word) || !wholeNumber(word, index) || index >= vertices)
        fail("has a face whose corners are not indices of its " + std::to_string(vertices) + " vertices (face " +
             std::to_string(f + 1) + ")");
      t[c] = static_cast<int64_t>(index);
    }
    soup.triangles.push_back(t);
  }
  if (soup.triangles.empty()) fail("has no faces");
  return soup;
}

// STL and OBJ through CGAL's readers.
TriangleSoup readWithCgal(const std::string& path, const std::string& what, const std::string& ext) {
  std::vector<KPoint> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool read = false;
  try {
    read = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception&) {
    read = false;
  }
  if (!read || polygons.empty())
    throw InputError(what + " is not a readable " + ext.substr(1) +
                     " file with triangles (truncated or damaged?): export it again");
  TriangleSoup soup;
  soup.points.reserve(points.size());
  for (const KPoint& p : points) soup.points.push_back({p.x(), p.y(), p.z()});
  soup.triangles.reserve(polygons.size());
  for (const auto& polygon : polygons) {
    for (std::size_t v : polygon)
      if (v >= points.size()) throw InputError(what + " refers to vertices it does not have: export it again");
    if (polygon.size() != 3)
      throw InputError(what + " has a face with " + std::to_string(polygon.size()) +
                       " corners: only triangles are read; triangulate the surface when exporting it");
    soup.triangles.push_back(
        {static_cast<int64_t>(polygon[0]), static_cast<int64_t>(polygon[1]), static_cast<int64_t>(polygon[2])});
  }
  return soup;
}

}  // namespace

TriangleSoup readTriangleSurfaceFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(what + " cannot be read: check the path");
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size == 0) throw InputError(what + " is empty: export the surface again");
  const std::string ext = lowerExtension(path);
  if (ext != ".stl" && ext != ".obj" && ext != ".off")
    throw InputError(what + ": triangle surfaces are read from .stl, .obj or .off files");
  TriangleSoup soup = ext == ".off" ? readOff(path, size, what) : readWithCgal(path, what, ext);
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    const Point3& p = soup.points[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      std::ostringstream at;
      at << p[0] << ", " << p[1] << ", " << p[2];
      throw InputError(what + " has a vertex with a coordinate that is not a finite number (vertex " +
                       std::to_string(i + 1) + ": " + at.str() + "): repair or export the surface again");
    }
  }
  return soup;
}

}  // namespace oraclemesh
