// The README's C++ example, verbatim between the markers (the test readme_snippet checks that
// they agree; example_quickstart runs it on a generated pair).
//   build/examples/quickstart robot.yaml layout.yaml
// README-BEGIN
#include <areamatch/areamatch.hpp>
#include <areamatch/io.hpp>
#include <iostream>

int main(int argc, char** argv) try {
  if (argc != 3) return std::cerr << "usage: quickstart SOURCE DEST\n", 2;
  const areamatch::OccupancyGrid robot = areamatch::load_map(argv[1]);   // ROS YAML, PNG or PGM
  const areamatch::OccupancyGrid layout = areamatch::load_map(argv[2]);
  areamatch::Matcher<> matcher;                  // the default policies; PaperMatcher = the paper
  matcher.params.allow_reflection = true;        // one map may be a mirror image of the other
  const areamatch::MatchResult m = matcher.match(robot, layout);  // segments both, then matches
  if (!m.ok) return std::cerr << "no match: " << m.reason << "\n", 1;
  std::cout << "rotation " << m.T_dest_source.rotation * 180.0 / areamatch::pi << " deg, translation "
            << m.T_dest_source.translation.transpose() << " m, p_correct " << m.p_correct << "\n";
  for (const auto& a : m.matched_areas) std::cout << "area " << a.source << " -> " << a.dest << "\n";
} catch (const areamatch::error& e) {  // missing file, corrupt image, bad parameter
  return std::cerr << e.what() << "\n", 2;
}
// README-END
