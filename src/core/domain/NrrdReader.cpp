#include "domain/NrrdReader.h"

#include <zlib.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "Error.h"

namespace oraclemesh {
namespace {

struct SampleType {
  int bytes;
  bool isSigned;
};

// Every spelling NRRD allows for the integer types a label image can use.
const std::map<std::string, SampleType>& integerTypes() {
  static const std::map<std::string, SampleType> types{
      {"signed char", {1, true}},         {"int8", {1, true}},           {"int8_t", {1, true}},
      {"uchar", {1, false}},              {"unsigned char", {1, false}}, {"uint8", {1, false}},
      {"uint8_t", {1, false}},            {"short", {2, true}},          {"short int", {2, true}},
      {"signed short", {2, true}},        {"signed short int", {2, true}}, {"int16", {2, true}},
      {"int16_t", {2, true}},             {"ushort", {2, false}},        {"unsigned short", {2, false}},
      {"unsigned short int", {2, false}}, {"uint16", {2, false}},        {"uint16_t", {2, false}},
      {"int", {4, true}},                 {"signed int", {4, true}},     {"int32", {4, true}},
      {"int32_t", {4, true}},             {"uint", {4, false}},          {"unsigned int", {4, false}},
      {"uint32", {4, false}},             {"uint32_t", {4, false}}};
  return types;
}

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

class NrrdFile {
 public:
  NrrdFile(std::string path, std::string inputName) : path_(std::move(path)), input_(std::move(inputName)) {}

  [[noreturn]] void fail(const std::string& problem, const std::string& fix) const {
    throw InputError("input '" + input_ + "': " + problem + " in '" + path_ + "': " + fix);
  }
  std::string describe() const { return "the image '" + path_ + "' of input '" + input_ + "'"; }

  static std::string readWhole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    std::ostringstream content;
    content << in.rdbuf();
    return content.str();
  }

  std::shared_ptr<const LabeledImage> read() {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec))
      throw InputError("input '" + input_ + "': cannot read the image file '" + path_ +
                       "': check the path (relative paths are taken from the job's folder)");
    const std::string content = readWhole(path_);
    if (content.compare(0, 7, "NRRD000") != 0 || content.size() < 8 || !std::isdigit(static_cast<unsigned char>(content[7])))
      fail("the file does not start with the NRRD magic 'NRRD000x'",
           "give a NRRD label image (.nrrd/.nhdr; 3D Slicer and SimpleITK write them)");
    size_t pos = content.find('\n');
    size_t dataStart = std::string::npos;
    while (pos != std::string::npos && pos + 1 <= content.size()) {
      const size_t begin = pos + 1;
      size_t end = content.find('\n', begin);
      std::string line = content.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty()) {  // the blank line that ends the header; attached data follows
        dataStart = end == std::string::npos ? content.size() : end + 1;
        break;
      }
      pos = end;
      if (line[0] == '#' || line.find(":=") != std::string::npos) continue;  // comment, key/value pair
      const size_t colon = line.find(": ");
      if (colon == std::string::npos) fail("the header line '" + line + "' is not 'field: value'", "fix the header");
      fields_[line.substr(0, colon)] = trim(line.substr(colon + 2));
      if (end == std::string::npos) break;
    }
    parseGeometry();
    std::string encoded;
    if (fields_.count("data file") || fields_.count("datafile")) {
      const std::string name = fields_.count("data file") ? fields_["data file"] : fields_["datafile"];
      if (name.rfind("LIST", 0) == 0 || name.find('%') != std::string::npos || name.find(' ') != std::string::npos)
        fail("the data is split over several files ('data file: " + name + "')",
             "save the image with its data in one file");
      std::filesystem::path dataPath(name);
      if (dataPath.is_relative()) dataPath = std::filesystem::path(path_).parent_path() / dataPath;
      if (!std::filesystem::is_regular_file(dataPath, ec))
        fail("the detached data file '" + dataPath.string() + "' does not exist",
             "keep the .raw/.raw.gz file next to the header or fix 'data file'");
      encoded = readWhole(dataPath.string());
    } else {
      if (dataStart == std::string::npos)
        fail("the header has no blank line and no 'data file', so there is no data",
             "the file is truncated; export the image again");
      encoded = content.substr(dataStart);
    }
    return std::make_shared<const LabeledImage>(size_, spacing_, origin_, decode(encoded), describe());
  }

 private:
  const std::string& required(const std::string& field) {
    auto it = fields_.find(field);
    if (it == fields_.end()) fail("the header has no '" + field + "' field", "export the image again as NRRD");
    return it->second;
  }

  std::vector<double> numbers(const std::string& text, const std::string& field) const {
    std::vector<double> values;
    std::string cleaned = text;
    for (char& c : cleaned)
      if (c == '(' || c == ')' || c == ',') c = ' ';
    std::istringstream in(cleaned);
    std::string token;
    while (in >> token) {
      if (token == "none") {
        values.push_back(std::nan(""));
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0') fail("'" + field + ": " + text + "' has a value that is not a number", "fix the header");
      values.push_back(v);
    }
    return values;
  }

  void parseGeometry() {
    const std::string dimension = required("dimension");
    if (dimension != "3")
      fail("the image has dimension " + dimension, "give a 3D label image (one label per voxel, 3 axes)");
    const std::string type = required("type");
    auto t = integerTypes().find(type);
    if (t == integerTypes().end())
      fail("the voxel type '" + type + "' is not supported",
           "labels must be integers: save the segmentation as uint8, int8, uint16, int16, uint32 or int32");
    type_ = t->second;
    const std::vector<double> sizes = numbers(required("sizes"), "sizes");
    if (sizes.size() != 3) fail("'sizes' does not give 3 numbers", "give a 3D label image");
    for (int a = 0; a < 3; ++a) {
      if (!(sizes[a] >= 1 && sizes[a] == std::floor(sizes[a]) && sizes[a] < 1e6))
        fail("'sizes' has an invalid axis size", "give positive integer sizes");
      size_[a] = static_cast<int64_t>(sizes[a]);
    }
    if (static_cast<double>(size_[0]) * size_[1] * size_[2] > 2e9)
      fail("the image has more than 2e9 voxels", "crop or downsample the segmentation");

    encoding_ = required("encoding");
    if (encoding_ == "gz") encoding_ = "gzip";
    if (encoding_ == "txt" || encoding_ == "text") encoding_ = "ascii";
    if (encoding_ != "raw" && encoding_ != "gzip" && encoding_ != "ascii")
      fail("the encoding '" + encoding_ + "' is not supported", "save the image with encoding raw or gzip");
    if (fields_.count("endian")) {
      if (fields_["endian"] != "little" && fields_["endian"] != "big")
        fail("'endian: " + fields_["endian"] + "' is neither little nor big", "fix the header");
      bigEndian_ = fields_["endian"] == "big";
    } else if (type_.bytes > 1 && encoding_ != "ascii") {
      fail("the header has no 'endian' field for " + std::to_string(8 * type_.bytes) + "-bit data",
           "add 'endian: little' (or big) to the header");
    }

    if (fields_.count("space dimension") && fields_["space dimension"] != "3")
      fail("'space dimension' is " + fields_["space dimension"] + "", "give an image in 3D space");
    if (fields_.count("space directions")) {
      const std::vector<double> d = numbers(fields_["space directions"], "space directions");
      if (d.size() != 9)
        fail("'space directions' does not give three 3D vectors", "give one direction vector per axis");
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) {
          const double v = d[3 * a + c];
          if (!std::isfinite(v)) fail("'space directions' has a non-finite entry", "give three finite vectors");
          const double scale = std::abs(d[3 * a]) + std::abs(d[3 * a + 1]) + std::abs(d[3 * a + 2]);
          if (c != a && std::abs(v) > 1e-9 * scale)
            fail("the voxel axes are rotated or sheared ('space directions: " + fields_["space directions"] + "')",
                 "resample the segmentation to an axis-aligned grid (e.g. 3D Slicer: Harden transform + Resample)");
        }
      for (int a = 0; a < 3; ++a) {
        const double v = d[4 * a];
        if (v == 0)
          fail("axis " + std::to_string(a) + " has spacing 0", "give positive voxel sizes in model units (mm)");
        spacing_[a] = std::abs(v);
        flip_[a] = v < 0;
      }
    } else if (fields_.count("spacings")) {
      const std::vector<double> s = numbers(fields_["spacings"], "spacings");
      if (s.size() != 3) fail("'spacings' does not give 3 numbers", "give one voxel size per axis");
      for (int a = 0; a < 3; ++a) {
        if (!(std::isfinite(s[a]) && s[a] > 0))
          fail("axis " + std::to_string(a) + " has spacing " + std::to_string(s[a]),
               "give positive voxel sizes in model units (mm)");
        spacing_[a] = s[a];
      }
    }  // neither: NRRD's default, unit voxels
    if (fields_.count("space origin")) {
      const std::vector<double> o = numbers(fields_["space origin"], "space origin");
      if (o.size() != 3 || !std::isfinite(o[0]) || !std::isfinite(o[1]) || !std::isfinite(o[2]))
        fail("'space origin' is not a finite 3D point", "give the centre of the first voxel as (x,y,z)");
      origin_ = {o[0], o[1], o[2]};
    }
    // A negative direction walks the axis backwards: the first voxel along it is the last
    // one we store, so the origin moves to the other end.
    for (int a = 0; a < 3; ++a)
      if (flip_[a]) origin_[a] -= static_cast<double>(size_[a] - 1) * spacing_[a];
  }

  // At most `wanted` bytes: the output grows with what the data really holds, so a header
  // that declares a huge image over a few bytes of gzip allocates nothing large.
  std::string inflateGzip(const std::string& compressed, size_t wanted) const {
    z_stream stream{};
    if (inflateInit2(&stream, 15 + 32) != Z_OK) fail("zlib could not start", "retry; report if it persists");
    std::string out;
    out.resize(std::max<size_t>(1, std::min(wanted, 4 * compressed.size() + 4096)));
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
    stream.avail_in = static_cast<uInt>(compressed.size());
    size_t produced = 0;
    int status = Z_OK;
    while (status == Z_OK && produced < wanted) {
      if (produced == out.size()) out.resize(std::min(wanted, out.size() * 2));
      stream.next_out = reinterpret_cast<Bytef*>(&out[produced]);
      stream.avail_out = static_cast<uInt>(std::min<size_t>(out.size() - produced, 1u << 30));
      const uInt before = stream.avail_out;
      status = inflate(&stream, Z_NO_FLUSH);
      produced += before - stream.avail_out;
      if (status == Z_BUF_ERROR && stream.avail_in == 0) break;  // input ran out: truncated
    }
    const std::string message = stream.msg ? stream.msg : "error";
    inflateEnd(&stream);
    if (status != Z_STREAM_END && status != Z_OK && status != Z_BUF_ERROR)
      fail("the gzip data is corrupt (zlib: " + message + ")",
           "export the image again");
    out.resize(produced);
    return out;
  }

  std::vector<int32_t> decode(std::string encoded) {
    const int64_t count = size_[0] * size_[1] * size_[2];
    auto skip = [&](const char* field, const char* alias, int64_t lowest) -> int64_t {
      const std::string key = fields_.count(field) ? field : alias;
      if (!fields_.count(key)) return 0;
      const std::vector<double> v = numbers(fields_[key], key);
      if (v.size() != 1 || v[0] != std::floor(v[0]) || v[0] < static_cast<double>(lowest) || !(v[0] < 1e15))
        fail("'" + key + ": " + fields_[key] + "' is not a valid count",
             std::string("give a whole number of ") + (lowest < 0 ? "bytes (or -1)" : "lines"));
      return static_cast<int64_t>(v[0]);
    };
    const int64_t lineSkip = skip("line skip", "lineskip", 0);
    int64_t byteSkip = skip("byte skip", "byteskip", -1);
    size_t dataStart = 0;
    for (int64_t l = 0; l < lineSkip; ++l) {
      const size_t nl = encoded.find('\n', dataStart);
      if (nl == std::string::npos) fail("'line skip' skips past the end of the data", "fix 'line skip'");
      dataStart = nl + 1;
    }
    encoded.erase(0, dataStart);
    // The data is checked to be there before the labels are allocated (a header may declare
    // billions of voxels over an empty file).
    if (encoding_ == "ascii" && static_cast<int64_t>(encoded.size()) + 1 < 2 * count)
      fail("the ascii data has " + std::to_string(encoded.size()) + " characters, too few for " + std::to_string(count) +
               " voxels",
           "the file is truncated or 'sizes' is wrong; export it again");
    const int64_t bytes = count * type_.bytes;
    std::string raw;
    if (encoding_ == "raw") {
      if (byteSkip == -1) byteSkip = std::max<int64_t>(0, static_cast<int64_t>(encoded.size()) - bytes);
      raw = encoded.substr(std::min<size_t>(encoded.size(), static_cast<size_t>(byteSkip)));
    } else if (encoding_ == "gzip") {
      if (byteSkip < 0) fail("'byte skip: -1' is only defined for raw data", "remove it or save the data raw");
      raw = inflateGzip(encoded, static_cast<size_t>(byteSkip + bytes));
      raw.erase(0, std::min<size_t>(raw.size(), static_cast<size_t>(byteSkip)));
    }
    if (encoding_ != "ascii" && static_cast<int64_t>(raw.size()) < bytes)
      fail("the data is truncated: " + std::to_string(raw.size()) + " bytes for " + std::to_string(count) + " voxels of " +
               std::to_string(type_.bytes) + " bytes (" + std::to_string(bytes) + " needed)",
           "export the image again; check 'sizes' and 'type'");
    std::vector<int32_t> labels(static_cast<size_t>(count));
    auto store = [&](int64_t n, int64_t value) {
      // NRRD order: axis 0 fastest. Flipped axes are stored reversed.
      int64_t idx[3] = {n % size_[0], (n / size_[0]) % size_[1], n / (size_[0] * size_[1])};
      for (int a = 0; a < 3; ++a)
        if (flip_[a]) idx[a] = size_[a] - 1 - idx[a];
      if (value > INT32_MAX || value < INT32_MIN)
        fail("the label " + std::to_string(value) + " does not fit in 32 bits", "renumber the labels");
      labels[static_cast<size_t>(idx[0] + size_[0] * (idx[1] + size_[1] * idx[2]))] = static_cast<int32_t>(value);
    };
    if (encoding_ == "ascii") {
      std::string cleaned = encoded;
      for (char& c : cleaned)
        if (c == ',') c = ' ';
      std::istringstream in(cleaned);
      for (int64_t n = 0; n < count; ++n) {
        long long v = 0;
        if (!(in >> v))
          fail("the ascii data ends after " + std::to_string(n) + " of " + std::to_string(count) + " voxels (or has a non-integer)",
               "the file is truncated or not a label image; export it again");
        store(n, v);
      }
      return labels;
    }
    const unsigned char* data = reinterpret_cast<const unsigned char*>(raw.data());
    for (int64_t n = 0; n < count; ++n) {
      const unsigned char* sample = data + n * type_.bytes;
      uint64_t u = 0;
      for (int byte = 0; byte < type_.bytes; ++byte) {
        const int shift = 8 * (bigEndian_ ? type_.bytes - 1 - byte : byte);
        u |= static_cast<uint64_t>(sample[byte]) << shift;
      }
      int64_t value = static_cast<int64_t>(u);
      if (type_.isSigned && (u >> (8 * type_.bytes - 1)) & 1) value -= int64_t{1} << (8 * type_.bytes);
      store(n, value);
    }
    return labels;
  }

  std::string path_, input_;
  std::map<std::string, std::string> fields_;
  SampleType type_{1, false};
  std::string encoding_;
  bool bigEndian_ = false;
  std::array<int64_t, 3> size_{};
  Point3 spacing_{1, 1, 1}, origin_{0, 0, 0};
  bool flip_[3] = {false, false, false};
};

}  // namespace

std::shared_ptr<const LabeledImage> readNrrdLabels(const std::string& path, const std::string& inputName) {
  return NrrdFile(path, inputName).read();
}

}  // namespace oraclemesh
