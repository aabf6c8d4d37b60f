// Fuzz target: the ROS map_server YAML reader and the pairs-manifest reader on arbitrary text.
#include <areamatch/io.hpp>
#include <eval/manifest.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)areamatch::parse_map_yaml(text, "fuzz/map.yaml");
  } catch (const areamatch::error&) {
  }
  try {
    (void)areamatch::parse_manifest(text, "fuzz/pairs.json");
  } catch (const areamatch::error&) {
  }
  return 0;
}
