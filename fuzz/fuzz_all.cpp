// The libFuzzer program for all four targets: the name it is started by picks the target.
// The build makes fuzz_image, fuzz_yaml, fuzz_segment and fuzz_match links to it, so
// `fuzz/fuzz_image CORPUS...` fuzzes the PNG/PGM decoders, and so on; libFuzzer's own flags work
// as with a program per target (its child processes are started by the same name).
#include "fuzz_targets.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

areamatch_fuzz::Target chosen = nullptr;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  const char* program = *argc > 0 ? (*argv)[0] : "";
  const char* slash = std::strrchr(program, '/');
  const char* name = slash ? slash + 1 : program;
  chosen = areamatch_fuzz::find_target(name);
  if (!chosen) {
    std::fprintf(stderr, "fuzz: started as '%s'; start this program by a target's name (%s)\n", name,
                 areamatch_fuzz::target_names);
    std::exit(2);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { return chosen(data, size); }
