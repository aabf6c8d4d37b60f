#pragma once
/// \file io/png.hpp
/// PNG reading (8/16-bit grey, grey+alpha, RGB, RGBA; colour is averaged to grey as map_server
/// does) and writing (8/16-bit grey, 8-bit RGB).

#include "../detail/file.hpp"
#include "../detail/stb.hpp"
#include "../error.hpp"
#include "../image.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace areamatch {

inline bool looks_like_png(const std::vector<unsigned char>& bytes) {
  static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return bytes.size() >= 8 && std::equal(signature, signature + 8, bytes.begin());
}

namespace detail {

/// The PNG checked chunk by chunk and with its empty IDAT chunks removed, before stb_image sees
/// it. Two things stb_image does with hostile files (both found by fuzz_image): it reallocates
/// its buffer to a chunk's declared length before checking that the file holds that many bytes
/// (a 75-byte file asked for 2 GB), and it memcpy's empty IDAT chunks into a still-null buffer
/// (undefined behaviour on a legal file). Throws `format_error` for a chunk running past the end.
inline std::vector<unsigned char> checked_png_chunks(const std::vector<unsigned char>& bytes, const std::string& name) {
  std::vector<unsigned char> out(bytes.begin(), bytes.begin() + std::min<std::size_t>(8, bytes.size()));
  out.reserve(bytes.size());
  std::size_t at = 8;
  while (at < bytes.size()) {
    if (at + 12 > bytes.size()) throw format_error(name + ": corrupt PNG (truncated chunk header)");
    const std::uint32_t length = (std::uint32_t(bytes[at]) << 24) | (std::uint32_t(bytes[at + 1]) << 16) |
                                 (std::uint32_t(bytes[at + 2]) << 8) | std::uint32_t(bytes[at + 3]);
    const std::string type(bytes.begin() + static_cast<std::ptrdiff_t>(at + 4), bytes.begin() + static_cast<std::ptrdiff_t>(at + 8));
    if (std::size_t(length) > bytes.size() - at - 12) {
      throw format_error(name + ": corrupt PNG (chunk '" + type + "' claims " + std::to_string(length) +
                         " bytes, the file has " + std::to_string(bytes.size() - at - 12) + " left)");
    }
    const std::size_t end = at + 12 + std::size_t(length);
    if (!(length == 0 && type == "IDAT")) {
      out.insert(out.end(), bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.begin() + static_cast<std::ptrdiff_t>(end));
    }
    if (type == "IEND") break;
    at = end;
  }
  return out;
}

}  // namespace detail

/// Decodes a PNG held in memory; `name` is used in error messages. Colour channels are averaged
/// (rounded) to one grey value; an alpha channel is kept in `GreyImage::alpha`.
inline GreyImage decode_png(const std::vector<unsigned char>& file_bytes, const std::string& name) {
  if (!looks_like_png(file_bytes)) throw format_error(name + ": not a PNG file (bad signature)");
  const std::vector<unsigned char> bytes = detail::checked_png_chunks(file_bytes, name);
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw format_error(name + ": PNG file too large");
  }
  const int length = static_cast<int>(bytes.size());
  int width = 0, height = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data(), length, &width, &height, &channels)) {
    throw format_error(name + ": corrupt PNG (" + stbi_failure_reason() + ")");
  }
  check_image_size(width, height, name);
  const bool sixteen = stbi_is_16_bit_from_memory(bytes.data(), length) != 0;

  GreyImage image(width, height, sixteen ? 65535 : 255);
  const bool has_alpha = channels == 2 || channels == 4;
  const int colour_channels = has_alpha ? channels - 1 : channels;
  if (has_alpha) image.alpha.assign(image.values.size(), 0);

  auto convert = [&](const auto* pixels) {
    const std::size_t count = image.values.size();
    if (channels == 1) {  // the common case: grey maps
      std::copy(pixels, pixels + count, image.values.begin());
      return;
    }
    for (std::size_t i = 0; i < count; ++i) {
      const auto* p = pixels + i * static_cast<std::size_t>(channels);
      unsigned sum = 0;
      for (int c = 0; c < colour_channels; ++c) sum += p[c];
      image.values[i] = static_cast<std::uint16_t>((sum + colour_channels / 2) / colour_channels);
      if (has_alpha) image.alpha[i] = p[colour_channels];
    }
  };
  int w = 0, h = 0, n = 0;
  if (sixteen) {
    std::unique_ptr<stbi_us, void (*)(void*)> pixels(
        stbi_load_16_from_memory(bytes.data(), length, &w, &h, &n, 0), stbi_image_free);
    if (!pixels) throw format_error(name + ": corrupt PNG (" + stbi_failure_reason() + ")");
    convert(pixels.get());
  } else {
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(bytes.data(), length, &w, &h, &n, 0), stbi_image_free);
    if (!pixels) throw format_error(name + ": corrupt PNG (" + stbi_failure_reason() + ")");
    convert(pixels.get());
  }
  return image;
}

inline GreyImage read_png(const std::string& path) { return decode_png(detail::read_file_bytes(path), path); }

namespace detail {

inline std::uint32_t png_crc(const unsigned char* data, std::size_t size, std::uint32_t crc = 0xffffffffu) {
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc;
}

inline void png_put_u32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>(v >> shift));
}

inline void png_chunk(std::vector<unsigned char>& out, const char type[4], const unsigned char* data,
                      std::size_t size) {
  png_put_u32(out, static_cast<std::uint32_t>(size));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  png_put_u32(out, png_crc(&out[start], size + 4) ^ 0xffffffffu);
}

/// A PNG from raw scanlines. `colour_type` 0 = grey, 2 = RGB; `bit_depth` 8 or 16; `samples` are
/// big-endian when 16-bit, `row_bytes` per row without the filter byte.
inline std::vector<unsigned char> encode_png_raw(int width, int height, int colour_type, int bit_depth,
                                                 const unsigned char* samples, std::size_t row_bytes) {
  // Each row gets filter "Up" (row minus the row above): maps are mostly long constant runs, which
  // this turns into zeros for the compressor.
  std::vector<unsigned char> filtered;
  filtered.reserve((row_bytes + 1) * static_cast<std::size_t>(height));
  for (int r = 0; r < height; ++r) {
    const unsigned char* row = samples + static_cast<std::size_t>(r) * row_bytes;
    filtered.push_back(r == 0 ? 0 : 2);
    if (r == 0) {
      filtered.insert(filtered.end(), row, row + row_bytes);
      continue;
    }
    const unsigned char* above = row - row_bytes;
    for (std::size_t i = 0; i < row_bytes; ++i) filtered.push_back(static_cast<unsigned char>(row[i] - above[i]));
  }
  int compressed_size = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> compressed(
      stbi_zlib_compress(filtered.data(), static_cast<int>(filtered.size()), &compressed_size, 8), std::free);
  if (!compressed) throw io_error("PNG encoder: out of memory");

  std::vector<unsigned char> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<unsigned char> header;
  png_put_u32(header, static_cast<std::uint32_t>(width));
  png_put_u32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {static_cast<unsigned char>(bit_depth), static_cast<unsigned char>(colour_type), 0, 0, 0});
  png_chunk(out, "IHDR", header.data(), header.size());
  png_chunk(out, "IDAT", compressed.get(), static_cast<std::size_t>(compressed_size));
  png_chunk(out, "IEND", nullptr, 0);
  return out;
}

}  // namespace detail

/// Encodes a grey PNG: 8-bit when `image.max_value` ≤ 255, otherwise 16-bit with the values
/// stored as they are (so a 16-bit label image keeps its ids). Alpha is not written.
inline std::vector<unsigned char> encode_png(const GreyImage& image) {
  check_image_size(image.width, image.height, "PNG encoder");
  const bool wide = image.max_value > 255;
  std::vector<unsigned char> samples;
  samples.reserve(image.values.size() * (wide ? 2 : 1));
  for (std::uint16_t v : image.values) {
    if (wide) samples.push_back(static_cast<unsigned char>(v >> 8));
    samples.push_back(static_cast<unsigned char>(v & 0xff));
  }
  return detail::encode_png_raw(image.width, image.height, 0, wide ? 16 : 8, samples.data(),
                                static_cast<std::size_t>(image.width) * (wide ? 2 : 1));
}

inline std::vector<unsigned char> encode_png(const RgbImage& image) {
  check_image_size(image.width, image.height, "PNG encoder");
  return detail::encode_png_raw(image.width, image.height, 2, 8, image.rgb.data(),
                                static_cast<std::size_t>(image.width) * 3);
}

template <class Image>
void write_png(const std::string& path, const Image& image) {
  const auto bytes = encode_png(image);
  detail::write_file_bytes(path, bytes.data(), bytes.size());
}

}  // namespace areamatch
