// The fuzz targets' seed corpus and every past finding (fuzz/regressions/), replayed with the
// ordinary compiler: each target's entry point runs once on every input, in a fixed order. A
// finding turned regression fails here if it comes back. The replay lives in the unit-test program
// because a program of its own cost one more compile of the whole library; the sanitizer build
// replays the same folders through its libFuzzer program instead (tests/CMakeLists.txt).
#include "../fuzz/fuzz_targets.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

/// The files of fuzz/corpus/TARGET and fuzz/regressions/TARGET, sorted.
std::vector<std::filesystem::path> replay_inputs(const std::string& target) {
  std::vector<std::filesystem::path> files;
  const std::filesystem::path fuzz_dir = std::filesystem::path(AREAMATCH_SOURCE_DIR) / "fuzz";
  for (const char* kind : {"corpus", "regressions"}) {
    const std::filesystem::path dir = fuzz_dir / kind / target;
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void replay(const char* target) {
  const areamatch_fuzz::Target run = areamatch_fuzz::find_target(target);
  REQUIRE(static_cast<bool>(run));
  const auto files = replay_inputs(target);
  REQUIRE_FALSE(files.empty());  // the seed corpus is part of the tree
  for (const auto& file : files) {
    INFO("input: ", file.string());
    // Read here, not with detail::read_file_bytes: that refuses an empty file, and an empty input
    // is a fuzz input like any other (libFuzzer saves one).
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Bad input may throw areamatch::error (caught inside the target); anything else escapes
    // and fails the case, as it would be a finding under libFuzzer.
    CHECK(run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()) == 0);
  }
  MESSAGE("replayed ", files.size(), " inputs");
}

}  // namespace

TEST_CASE("fuzz_image: the corpus and past findings replay cleanly") { replay("fuzz_image"); }
TEST_CASE("fuzz_yaml: the corpus and past findings replay cleanly") { replay("fuzz_yaml"); }
TEST_CASE("fuzz_segment: the corpus and past findings replay cleanly") { replay("fuzz_segment"); }
TEST_CASE("fuzz_match: the corpus and past findings replay cleanly") { replay("fuzz_match"); }
