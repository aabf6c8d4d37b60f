// Builds a synthetic building, saves and reloads it: proves the headers and the io target link.
#include <areamatch/areamatch.hpp>
#include <areamatch/io.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  areamatch::BuildingParams params;
  params.width_m = 12.0;
  params.height_m = 10.0;
  const auto building = areamatch::generate_building(params, 1);
  const std::string path = std::string(argc > 1 ? argv[1] : ".") + "/consumer_map.png";
  const std::string yaml = areamatch::save_map(building.layout, path);
  const auto loaded = areamatch::load_map(yaml);
  if (loaded != building.layout) {
    std::puts("round trip differs");
    return 1;
  }
  std::printf("areamatch %s consumer OK: %dx%d cells\n", areamatch::version_string, loaded.width(), loaded.height());
  return 0;
}
