#include "job/JobJson.h"

#include <cmath>
#include <filesystem>
#include <system_error>

#include "Error.h"

namespace oraclemesh::jobjson {

namespace {

// Where the nesting first goes past kMaxDepth (line counted from 1), or 0: a scan of the
// text, so that nothing deep is ever built.
size_t lineTooDeep(const std::string& text) {
  int depth = 0;
  size_t line = 1;
  bool inString = false, escaped = false;
  for (char c : text) {
    if (c == '\n') ++line;
    if (inString) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        inString = false;
      continue;
    }
    if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxDepth) return line;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return 0;
}

}  // namespace

void requireJobSize(uintmax_t bytes, const std::string& file) {
  if (bytes <= kMaxBytes) return;
  throw InputError((file.empty() ? std::string("the job") : "the job file '" + file + "'") + " is " +
                   std::to_string(bytes) + " bytes of JSON, more than the limit of " + std::to_string(kMaxBytes) +
                   " bytes (" + std::to_string(kMaxBytes >> 30) +
                   " GiB): give large surfaces as STL/OBJ/OFF files instead of 'surface' lists");
}

void requireJobFileSize(const std::string& path) {
  std::error_code error;
  const uintmax_t bytes = std::filesystem::file_size(path, error);
  if (!error) requireJobSize(bytes, path);
}

json parse(const std::string& text) {
  requireJobSize(text.size());
  if (const size_t line = lineTooDeep(text))
    throw InputError("the job nests lists and objects more than " + std::to_string(kMaxDepth) +
                     " levels deep (line " + std::to_string(line) +
                     "): the job contract needs at most 6 levels; check how the job file was written");
  try {
    return json::parse(text);
  } catch (const json::out_of_range& e) {  // 406: a number beyond double range
    throw InputError(std::string("the job has a number too large for a double: ") + e.what() +
                     ": numbers must be finite (at most about 1.8e308); give sizes in model units (mm)");
  } catch (const json::exception& e) {
    throw InputError(std::string("the job is not valid JSON: ") + e.what());
  }
}

std::string shortDump(const json& value) {
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

double number(const json& value, const std::string& path, const std::string& fix) {
  if (!value.is_number()) throw InputError(path + " must be a number, got " + shortDump(value) + ": " + fix);
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw InputError(path + " = " + shortDump(value) + " is not a finite number: " + fix);
  return v;
}

double positiveNumber(const json& value, const std::string& path, const std::string& fix) {
  const double v = number(value, path, fix);
  if (!(v > 0)) throw InputError(path + " = " + shortDump(value) + " is not a positive finite number: " + fix);
  return v;
}

int64_t integer(const json& value, const std::string& path, int64_t lowest, int64_t highest, const std::string& fix) {
  const std::string range = "a whole number from " + std::to_string(lowest) + " to " + std::to_string(highest);
  bool inRange = false;
  int64_t v = 0;
  if (value.is_number_unsigned()) {
    const uint64_t u = value.get<uint64_t>();
    inRange = u <= static_cast<uint64_t>(highest) && (lowest <= 0 || u >= static_cast<uint64_t>(lowest));
    v = static_cast<int64_t>(u);
  } else if (value.is_number_integer()) {
    v = value.get<int64_t>();
    inRange = v >= lowest && v <= highest;
  } else if (value.is_number_float()) {
    const double d = value.get<double>();
    // Exact comparisons: doubles hold every integer up to 2^53, and larger limits are not needed.
    inRange = std::isfinite(d) && d == std::floor(d) && d >= static_cast<double>(lowest) &&
              d <= static_cast<double>(highest);
    if (inRange) v = static_cast<int64_t>(d);
  } else {
    throw InputError(path + " must be " + range + ", got " + shortDump(value) + ": " + fix);
  }
  if (!inRange) throw InputError(path + " = " + shortDump(value) + " is not " + range + ": " + fix);
  return v;
}

bool boolean(const json& value, const std::string& path) {
  if (!value.is_boolean()) throw InputError(path + " must be true or false, got " + shortDump(value));
  return value.get<bool>();
}

std::string string(const json& value, const std::string& path, const std::string& fix) {
  if (!value.is_string()) throw InputError(path + " must be a string, got " + shortDump(value) + ": " + fix);
  return value.get<std::string>();
}

}  // namespace oraclemesh::jobjson
