// The fuzz targets without libFuzzer, as one program: `replay_fuzz TARGET INPUT...` runs the
// target's entry point on every file in the folders (or files) given. The test suite uses it to
// replay the seed corpus and every past finding (fuzz/regressions/) with the ordinary compiler,
// and under the sanitizers in scripts/sanitize.sh. The four targets are one unit (fuzz_targets.hpp).
#include "fuzz_targets.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  const areamatch_fuzz::Target run = argc > 1 ? areamatch_fuzz::find_target(argv[1]) : nullptr;
  if (!run) {
    std::fprintf(stderr, "usage: replay_fuzz %s INPUT...\n", areamatch_fuzz::target_names);
    return 2;
  }
  std::vector<std::filesystem::path> files;
  for (int i = 2; i < argc; ++i) {
    const std::filesystem::path p(argv[i]);
    if (std::filesystem::is_directory(p)) {
      for (const auto& entry : std::filesystem::directory_iterator(p))
        if (entry.is_regular_file()) files.push_back(entry.path());
    } else if (std::filesystem::is_regular_file(p)) {
      files.push_back(p);
    } else {
      std::fprintf(stderr, "replay: %s: no such file or folder\n", argv[i]);
      return 2;
    }
  }
  std::sort(files.begin(), files.end());  // a fixed order: the same run every time
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("replayed %zu inputs\n", files.size());
  return files.empty() ? 1 : 0;
}
