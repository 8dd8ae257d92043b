// Did-you-mean for mistyped names (see closest_name.h).
#include "io/closest_name.h"

#include <algorithm>

namespace xsect {

int editDistance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  // Three rows of the optimal-string-alignment table.
  std::vector<int> before(m + 1), previous(m + 1), current(m + 1);
  for (std::size_t j = 0; j <= m; ++j) previous[j] = int(j);
  for (std::size_t i = 1; i <= n; ++i) {
    current[0] = int(i);
    for (std::size_t j = 1; j <= m; ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        current[j] = std::min(current[j], before[j - 2] + 1);
    }
    before.swap(previous);
    previous.swap(current);
  }
  return previous[m];
}

std::optional<std::string> closestName(const std::string& word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  int bestDistance = 0;
  for (const std::string& c : candidates) {
    const int d = editDistance(word, c);
    const int allowed = std::clamp(int(std::max(word.size(), c.size())) / 3, 1, 3);
    if (d == 0 || d > allowed) continue;
    if (!best || d < bestDistance) best = c, bestDistance = d;
  }
  return best;
}

std::string didYouMeanText(const std::string& suggestion) {
  return suggestion.empty() ? "" : " (did you mean '" + suggestion + "'?)";
}

std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  return didYouMeanText(closestName(word, candidates).value_or(""));
}

}  // namespace xsect
