//! GitHub's anchor of a Markdown heading, for the tests that check links into the docs and
//! the report.

/// The anchor of `heading` (with or without its leading `#`s): lower case, spaces to
/// hyphens, punctuation other than `-` and `_` dropped.
pub fn github_anchor(heading: &str) -> String {
    heading
        .trim_start_matches('#')
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}
