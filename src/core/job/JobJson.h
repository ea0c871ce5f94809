#pragma once
// Reading the job's JSON safely: the text within size and nesting limits, and typed values
// that name their JSON path (`inputs[2].material`) and the fix when they are wrong. Nothing
// here lets a nlohmann exception (which names no key) reach a user.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

namespace oraclemesh::jobjson {

using nlohmann::json;

// Deeper than any job needs (a polyline point is at depth 6); keeps recursive code (the
// parser's destructor, dump()) far from the stack's end.
constexpr int kMaxDepth = 64;
// 1 GiB of text: a triangle surface of ~10 million triangles sent from FreeCAD fits.
constexpr size_t kMaxBytes = size_t{1} << 30;

// InputError naming kMaxBytes and the fix when a job of `bytes` bytes is over it; `file` is the
// job file's path, or empty for JSON text.
void requireJobSize(uintmax_t bytes, const std::string& file = "");
// The same for the job file at `path`, by its size on disk, before anything of it is read
// (a file that cannot be measured, a pipe, is left to the reading).
void requireJobFileSize(const std::string& path);

// InputError for text over kMaxBytes, nested deeper than kMaxDepth (with the line), not JSON,
// or with a number out of double range (1e999).
json parse(const std::string& text);

// `value` as JSON, cut to about 60 characters for messages.
std::string shortDump(const json& value);

// A finite number at `path` (InputError naming path, value and `fix` otherwise).
double number(const json& value, const std::string& path, const std::string& fix);
// A finite number > 0.
double positiveNumber(const json& value, const std::string& path, const std::string& fix);
// A whole number in [lowest, highest] (an integer, or a float with no fraction: 2.0).
int64_t integer(const json& value, const std::string& path, int64_t lowest, int64_t highest, const std::string& fix);
bool boolean(const json& value, const std::string& path);
std::string string(const json& value, const std::string& path, const std::string& fix);

}  // namespace oraclemesh::jobjson
