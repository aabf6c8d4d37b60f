// A clusterer without `cluster(const std::vector<Hypothesis>&) const`: the Clusterer message.
#include <areamatch/matcher.hpp>
struct NoCluster { int cluster(int) const { return 0; } };
int main() { areamatch::Matcher<areamatch::VoronoiSegmenter, areamatch::PaperFeatures, areamatch::PaperWeights, NoCluster> m; (void)m; }
