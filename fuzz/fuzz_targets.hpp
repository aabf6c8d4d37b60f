#pragma once
// The four fuzz targets compiled into one unit, each entry point renamed, with a table from
// target name to entry point. Each target alone costs a compile of the whole library, so both
// places that run them — the libFuzzer program (fuzz_all.cpp) and the replay inside the unit-test
// program (tests/test_fuzz_replay.cpp) — build all four from this one header and pick a target at
// run time.
#define LLVMFuzzerTestOneInput areamatch_fuzz_image
#include "fuzz_image.cpp"
#undef LLVMFuzzerTestOneInput
#define LLVMFuzzerTestOneInput areamatch_fuzz_yaml
#include "fuzz_yaml.cpp"
#undef LLVMFuzzerTestOneInput
#define LLVMFuzzerTestOneInput areamatch_fuzz_segment
#include "fuzz_segment.cpp"
#undef LLVMFuzzerTestOneInput
#define LLVMFuzzerTestOneInput areamatch_fuzz_match
#include "fuzz_match.cpp"
#undef LLVMFuzzerTestOneInput

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace areamatch_fuzz {

using Target = int (*)(const std::uint8_t*, std::size_t);

/// The target of that name (fuzz_image, fuzz_yaml, fuzz_segment, fuzz_match), or nullptr.
inline Target find_target(const char* name) {
  const struct {
    const char* name;
    Target run;
  } targets[] = {{"fuzz_image", areamatch_fuzz_image},
                 {"fuzz_yaml", areamatch_fuzz_yaml},
                 {"fuzz_segment", areamatch_fuzz_segment},
                 {"fuzz_match", areamatch_fuzz_match}};
  for (const auto& t : targets)
    if (name && std::strcmp(name, t.name) == 0) return t.run;
  return nullptr;
}

constexpr const char* target_names = "fuzz_image|fuzz_yaml|fuzz_segment|fuzz_match";

}  // namespace areamatch_fuzz
