#pragma once
// The readers take paths: each fuzz input is written to one file per process (in /dev/shm
// when there is one, so the fuzzer is not slowed down by a disk).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace oraclemesh::fuzz {

inline std::string writeInput(const uint8_t* data, size_t size, const std::string& extension) {
  static const std::string path = [&] {
    const std::filesystem::path folder = std::filesystem::exists("/dev/shm") ? "/dev/shm" : "/tmp";
    return (folder / ("oraclemesh-fuzz-" + std::to_string(getpid()) + extension)).string();
  }();
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) __builtin_trap();
  if (size) std::fwrite(data, 1, size, file);
  std::fclose(file);
  return path;
}

}  // namespace oraclemesh::fuzz
