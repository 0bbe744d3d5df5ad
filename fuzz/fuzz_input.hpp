#pragma once
// Shared by the fuzz targets: the bytes of one input written to a private temporary file (the
// readers under test take paths), and the rule every target enforces -- an input may be rejected
// only with adamss::InputError (or NumericalError); anything else (another exception, a crash,
// undefined behaviour caught by the sanitizers, a leak) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace adamss::fuzz {

inline std::filesystem::path scratch_file(const char* suffix) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("adamss-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir / (std::string("input") + suffix);
}

inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size, const char* suffix) {
  const auto p = scratch_file(suffix);
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p;
}

}  // namespace adamss::fuzz
