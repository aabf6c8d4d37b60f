#pragma once
/// \file detail/file.hpp
/// Whole-file reads and writes with errors that name the file and the reason.

#include "../error.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace areamatch::detail {

/// Reads a regular file into memory. Throws `io_error` when it is missing, a directory, unreadable
/// or empty, and when it is larger than `max_bytes`.
inline std::vector<unsigned char> read_file_bytes(const std::string& path,
                                                  std::size_t max_bytes = std::size_t(1) << 31) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw io_error(path + ": cannot open (" + std::strerror(errno) + ")");
  }
  if (S_ISDIR(info.st_mode)) throw io_error(path + ": is a directory, not a file");
  if (!S_ISREG(info.st_mode)) throw io_error(path + ": is not a regular file");
  if (info.st_size == 0) throw format_error(path + ": file is empty");
  if (static_cast<std::size_t>(info.st_size) > max_bytes) {
    throw io_error(path + ": file is larger than " + std::to_string(max_bytes) + " bytes");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error(path + ": cannot open for reading");
  std::vector<unsigned char> bytes(static_cast<std::size_t>(info.st_size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::size_t>(in.gcount()) != bytes.size()) throw io_error(path + ": read failed");
  return bytes;
}

inline void write_file_bytes(const std::string& path, const unsigned char* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw io_error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.flush();
  if (!out) throw io_error(path + ": write failed");
}

inline void write_file_text(const std::string& path, const std::string& text) {
  write_file_bytes(path, reinterpret_cast<const unsigned char*>(text.data()), text.size());
}

/// The folder part of a path ("" for a bare file name), and a path joined to a folder.
inline std::string parent_folder(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}
inline std::string file_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}
inline std::string lowercase_extension(const std::string& path) {
  const std::string name = file_name(path);
  const auto dot = name.find_last_of('.');
  std::string ext = dot == std::string::npos ? std::string() : name.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace areamatch::detail
