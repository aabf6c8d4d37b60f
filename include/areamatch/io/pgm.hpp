#pragma once
/// \file io/pgm.hpp
/// Netpbm grey maps: P5 (binary) and P2 (ASCII), 8-bit (maxval ≤ 255) and 16-bit (maxval ≤ 65535,
/// big-endian samples). map_saver writes P5 with maxval 255.

#include "../detail/file.hpp"
#include "../error.hpp"
#include "../image.hpp"

#include <cctype>
#include <cstdint>
#include <string>
#include <vector>

namespace areamatch {
namespace detail {

/// Reads the whitespace- and comment-separated header tokens of a Netpbm file.
class PgmHeaderReader {
 public:
  PgmHeaderReader(const std::vector<unsigned char>& bytes, const std::string& name)
      : bytes_(bytes), name_(name) {}

  long long read_number(const char* what) {
    skip_space_and_comments();
    if (pos_ >= bytes_.size() || !std::isdigit(bytes_[pos_])) {
      throw format_error(name_ + ": PGM header: missing or invalid " + std::string(what));
    }
    long long value = 0;
    while (pos_ < bytes_.size() && std::isdigit(bytes_[pos_])) {
      value = value * 10 + (bytes_[pos_++] - '0');
      if (value > 1000000000LL) throw format_error(name_ + ": PGM header: " + what + " is too large");
    }
    return value;
  }
  std::size_t position() const { return pos_; }
  void set_position(std::size_t pos) { pos_ = pos; }

 private:
  void skip_space_and_comments() {
    while (pos_ < bytes_.size()) {
      if (bytes_[pos_] == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r') ++pos_;
      } else if (std::isspace(bytes_[pos_])) {
        ++pos_;
      } else {
        break;
      }
    }
  }
  const std::vector<unsigned char>& bytes_;
  std::string name_;
  std::size_t pos_ = 2;
};

}  // namespace detail

/// True when the bytes start like a grey Netpbm file (P2 or P5).
inline bool looks_like_pgm(const std::vector<unsigned char>& bytes) {
  return bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '5' || bytes[1] == '2');
}

/// Decodes a PGM held in memory; `name` is used in error messages.
inline GreyImage decode_pgm(const std::vector<unsigned char>& bytes, const std::string& name) {
  if (!looks_like_pgm(bytes)) throw format_error(name + ": not a PGM file (no P2/P5 magic number)");
  const bool binary = bytes[1] == '5';
  detail::PgmHeaderReader header(bytes, name);
  const long long width = header.read_number("width");
  const long long height = header.read_number("height");
  const long long max_value = header.read_number("maxval");
  check_image_size(width, height, name);
  if (max_value < 1 || max_value > 65535) {
    throw format_error(name + ": unsupported PGM maxval " + std::to_string(max_value) +
                       " (must be 1..65535)");
  }
  GreyImage image(static_cast<int>(width), static_cast<int>(height), static_cast<int>(max_value));
  const std::size_t count = image.values.size();
  if (binary) {
    // Exactly one whitespace byte separates maxval from the samples.
    std::size_t pos = header.position();
    if (pos >= bytes.size() || !std::isspace(bytes[pos])) {
      throw format_error(name + ": PGM header: no whitespace after maxval");
    }
    ++pos;
    const std::size_t bytes_per_sample = max_value > 255 ? 2 : 1;
    if (bytes.size() - pos < count * bytes_per_sample) {
      throw format_error(name + ": truncated PGM: expected " + std::to_string(count * bytes_per_sample) +
                         " bytes of pixel data, found " + std::to_string(bytes.size() - pos));
    }
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint16_t v = bytes_per_sample == 2
                                  ? static_cast<std::uint16_t>((bytes[pos + 2 * i] << 8) | bytes[pos + 2 * i + 1])
                                  : bytes[pos + i];
      if (v > max_value) {
        throw format_error(name + ": PGM sample " + std::to_string(v) + " exceeds maxval " +
                           std::to_string(max_value));
      }
      image.values[i] = v;
    }
  } else {
    for (std::size_t i = 0; i < count; ++i) {
      long long v = 0;
      try {
        v = header.read_number("sample");
      } catch (const format_error&) {
        throw format_error(name + ": truncated PGM: expected " + std::to_string(count) +
                           " samples, found " + std::to_string(i));
      }
      if (v > max_value) {
        throw format_error(name + ": PGM sample " + std::to_string(v) + " exceeds maxval " +
                           std::to_string(max_value));
      }
      image.values[i] = static_cast<std::uint16_t>(v);
    }
  }
  return image;
}

inline GreyImage read_pgm(const std::string& path) { return decode_pgm(detail::read_file_bytes(path), path); }

/// Encodes a binary PGM (P5). 16-bit when `image.max_value` > 255. The alpha channel is dropped.
inline std::vector<unsigned char> encode_pgm(const GreyImage& image) {
  const std::string header = "P5\n" + std::to_string(image.width) + " " + std::to_string(image.height) +
                             "\n" + std::to_string(image.max_value) + "\n";
  std::vector<unsigned char> out(header.begin(), header.end());
  const bool wide = image.max_value > 255;
  out.reserve(out.size() + image.values.size() * (wide ? 2 : 1));
  for (std::uint16_t v : image.values) {
    if (wide) out.push_back(static_cast<unsigned char>(v >> 8));
    out.push_back(static_cast<unsigned char>(v & 0xff));
  }
  return out;
}

inline void write_pgm(const std::string& path, const GreyImage& image) {
  const auto bytes = encode_pgm(image);
  detail::write_file_bytes(path, bytes.data(), bytes.size());
}

}  // namespace areamatch
