// A FeatureSet member that is not a feature: the FeatureSet message comes first.
#include <areamatch/matcher.hpp>
struct NotAFeature { double cost(int, int) const { return 0; } };
int main() { areamatch::Matcher<areamatch::VoronoiSegmenter, areamatch::FeatureSet<areamatch::AreaSize, NotAFeature>, areamatch::PaperWeights> m; (void)m; }
