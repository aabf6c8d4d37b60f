#pragma once
/// \file version.hpp
/// The library version. CMake reads these three macros, so they are the single source of truth.

#define AREAMATCH_VERSION_MAJOR 0
#define AREAMATCH_VERSION_MINOR 1
#define AREAMATCH_VERSION_PATCH 0

namespace areamatch {

/// "MAJOR.MINOR.PATCH" of the headers in use.
inline constexpr const char* version_string = "0.1.0";

}  // namespace areamatch
