// Fuzz target: the PNG and PGM decoders and map_server thresholding on arbitrary bytes.
#include <areamatch/io.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<unsigned char> bytes(data, data + size);
  try {
    areamatch::GreyImage image;
    if (areamatch::looks_like_png(bytes)) image = areamatch::decode_png(bytes, "fuzz.png");
    else if (areamatch::looks_like_pgm(bytes)) image = areamatch::decode_pgm(bytes, "fuzz.pgm");
    else return 0;
    const auto grid = areamatch::grid_from_image(image, areamatch::OccupancyThresholds{}, 0.05, {});
    (void)grid.count();
  } catch (const areamatch::error&) {
    // bad input, reported: fine
  }
  return 0;
}
