#pragma once
// Helpers shared by the test executables: temp folders, the shared data folder, file writing.

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace areamatch_test {

inline bool& shared_skip_flag() {
  static bool flag = false;  // test-only state: set when a test found ../shared missing
  return flag;
}
inline bool skipped_for_missing_shared() { return shared_skip_flag(); }

/// True in the sanitizer run (scripts/sanitize.sh sets AREAMATCH_QUICK_TESTS=1): unoptimised
/// code with ASan + UBSan runs ~300 times slower, so the long loops run a few iterations of the
/// same code instead of all of them (the Release run keeps the full counts).
inline bool quick_tests() {
  const char* env = std::getenv("AREAMATCH_QUICK_TESTS");
  return env && *env && std::string(env) != "0";
}

/// The generated buildings the accept/reject decision was calibrated on (scripts/calibration_data.sh
/// draws them from these seeds with the default building parameters: xA, xB, xC, hhsyn, hhx). A
/// test that judges the decision on generated buildings draws its own, from `test_seed_base` on,
/// so that what it checks is out of sample.
inline bool calibration_seed(std::uint64_t seed) {
  return (seed >= 100 && seed < 120) || (seed >= 200 && seed < 220) || (seed >= 300 && seed < 320) ||
         (seed >= 500 && seed < 550) || (seed >= 600 && seed < 612);
}
inline constexpr std::uint64_t test_seed_base = 10'000;

inline bool is_dir(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode);
}

#ifdef AREAMATCH_SHARED_DIR
/// The shared data folder (maps/, pairs.json), or "" when it is not there.
inline std::string shared_dir() {
  const char* env = std::getenv("AREAMATCH_SHARED_DIR");
  const std::string dir = env && *env ? env : AREAMATCH_SHARED_DIR;
  if (is_dir(dir + "/maps")) return dir;
  shared_skip_flag() = true;
  return "";
}

/// A folder for the files of the test file that calls it (`file`: the caller's, by default), so
/// that test files run in parallel from one program never write to the same place.
inline std::string temp_dir(const char* file = __builtin_FILE()) {
  std::string name = file;
  name = name.substr(name.find_last_of('/') + 1);
  name = name.substr(0, name.find('.'));
  const std::string root = AREAMATCH_TEST_TMP, dir = root + "/" + name;
  ::mkdir(root.c_str(), 0755);
  ::mkdir(dir.c_str(), 0755);
  return dir;
}

#endif

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace areamatch_test
