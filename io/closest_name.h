// The name a mistyped one was most likely meant to be: the candidate at the smallest edit distance
// (Damerau-Levenshtein: insertions, deletions, substitutions and swaps of neighbours count 1),
// provided it is close enough to be a typo (at most a third of the longer word's letters, at least
// 1, at most 3). Used for the did-you-mean of unknown configuration keys and choice names.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace xsect {

/// The edit distance between a and b (adjacent transpositions count 1).
int editDistance(const std::string& a, const std::string& b);

/// The candidate closest to `word`, if one is within typo distance; ties go to the first given.
std::optional<std::string> closestName(const std::string& word, const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" for the closest candidate, or "" when none is close.
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

/// " (did you mean 'suggestion'?)", or "" for an empty suggestion.
std::string didYouMeanText(const std::string& suggestion);

}  // namespace xsect
