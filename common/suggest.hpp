#pragma once
// "Did you mean ...?" for names a user typed: scene keys, force terms, laws, units, subcommands,
// options. The closest candidate by edit distance, if it is close enough to be a typo.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace adamss {

/// Optimal-string-alignment distance between `a` and `b`: the number of single-character
/// insertions, deletions, substitutions and transpositions of two adjacent characters that turn
/// one into the other ("rnu" -> "run": 1, "tend" -> "t_end": 1). A substitution that only
/// changes letter case counts as one.
[[nodiscard]] std::size_t edit_distance(std::string_view a, std::string_view b);

/// The candidate closest to `word`, if its distance is at most max(1, |word| / 3) (a typo, not
/// another word) and it is not `word` itself; on equal distance the one closest in length (a
/// swap "a_sf" -> "a_fs" before a deletion "a_f"), then the first. A candidate that
/// starts with `word` (|word| >= 3) counts as at the limit: "--fiber" suggests "--fiber-out".
[[nodiscard]] std::optional<std::string> closest_name(std::string_view word,
                                                      const std::vector<std::string>& candidates);

/// "; did you mean 'NAME'?" with closest_name(word, candidates), or "" when none is close.
[[nodiscard]] std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace adamss
