// A selection without `select(const SelectionInputs&, MatchStatistics&) const`: the Selection message.
#include <areamatch/matcher.hpp>
struct NoSelect { int select(int) const { return 0; } };
int main() {
  areamatch::Matcher<areamatch::VoronoiSegmenter, areamatch::PaperFeatures, areamatch::PaperWeights,
                     areamatch::PoseClusterer, NoSelect> m;
  (void)m;
}
