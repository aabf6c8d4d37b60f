#!/usr/bin/env bash
# Measures what including areamatch costs a program's build (README, "Compile time"): the README's
# quickstart at -O2 and -O0, with only the headers it uses, with a precompiled header, and the
# one-unit pattern (only matching.cpp includes areamatch; app.cpp sees a small header of its own).
# One compile at a time, in a scratch folder; about 8 minutes on 2 cores.
#   scripts/compile_time.sh [CXX]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cxx="${1:-g++}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
sed -n '/README-BEGIN/,/README-END/p' "$here/examples/quickstart.cpp" | sed '1d;$d' > quick.cpp
sed 's|#include <areamatch/areamatch.hpp>|#include <areamatch/matcher.hpp>|' quick.cpp > quick_min.cpp
printf '#include <areamatch/areamatch.hpp>\n#include <areamatch/io.hpp>\n' > pch.hpp
cat > matching.hpp <<'EOF'
#pragma once
#include <string>
#include <utility>
#include <vector>
struct Placement {
  bool ok = false;
  std::string reason;
  double rotation_deg = 0.0, x_m = 0.0, y_m = 0.0;
  std::vector<std::pair<int, int>> rooms;  // source area -> destination area
};
Placement match_map_files(const std::string& source, const std::string& dest);
EOF
cat > matching.cpp <<'EOF'
#include "matching.hpp"
#include <areamatch/matcher.hpp>
#include <areamatch/io.hpp>
Placement match_map_files(const std::string& source, const std::string& dest) {
  areamatch::Matcher<> matcher;
  matcher.params.allow_reflection = true;
  const areamatch::MatchResult m = matcher.match(areamatch::load_map(source), areamatch::load_map(dest));
  Placement out{m.ok, m.reason, m.T_dest_source.rotation * 180.0 / areamatch::pi, m.T_dest_source.translation.x(),
                m.T_dest_source.translation.y(), {}};
  for (const auto& a : m.matched_areas) out.rooms.emplace_back(a.source, a.dest);
  return out;
}
EOF
cat > app.cpp <<'EOF'
#include "matching.hpp"
#include <iostream>
int main(int argc, char** argv) {
  if (argc != 3) return 2;
  const Placement p = match_map_files(argv[1], argv[2]);
  std::cout << (p.ok ? "rotation " + std::to_string(p.rotation_deg) : "no match: " + p.reason) << "\n";
}
EOF
flags=(-std=c++17 -I"$here/include" -isystem /usr/include/eigen3)
timed() {  # LABEL COMMAND...: the command's wall time
  local label="$1" start end
  shift
  start=$(date +%s.%N)
  "$@"
  end=$(date +%s.%N)
  printf '%-48s %6.1f s\n' "$label" "$(echo "$end - $start" | bc)"
}
timed "quickstart, -O2" "$cxx" "${flags[@]}" -O2 -c quick.cpp -o quick.o
timed "quickstart, -O0" "$cxx" "${flags[@]}" -O0 -c quick.cpp -o quick0.o
timed "quickstart, only matcher.hpp + io.hpp, -O2" "$cxx" "${flags[@]}" -O2 -c quick_min.cpp -o quick_min.o
timed "precompiled header, -O2 (once)" "$cxx" "${flags[@]}" -O2 -x c++-header pch.hpp -o pch.hpp.gch
timed "quickstart with it, -O2" "$cxx" "${flags[@]}" -O2 -include pch.hpp -c quick.cpp -o quick_pch.o
timed "one unit: matching.cpp, -O2" "$cxx" "${flags[@]}" -O2 -c matching.cpp -o matching.o
timed "one unit: app.cpp, -O2 (each edit)" "$cxx" -std=c++17 -O2 -c app.cpp -o app.o
timed "one unit: link" "$cxx" app.o matching.o -o app -lyaml-cpp
