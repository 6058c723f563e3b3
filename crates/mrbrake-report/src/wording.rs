//! Small wording helpers shared by the text reports: counts with the right plural, and paths
//! quoted for a shell when a report prints a command to run.

use std::path::Path;

/// `n` and the noun, singular for exactly one: `count(1, "design", "designs")` is "1 design",
/// `count(2, …)` "2 designs", `count(0, …)` "0 designs".
pub fn count(n: usize, singular: &str, plural: &str) -> String {
    if n == 1 { format!("1 {singular}") } else { format!("{n} {plural}") }
}

/// `path` as a POSIX shell word: unchanged when it holds only characters a shell leaves alone,
/// otherwise in single quotes (a `'` inside written `'\''`), so a printed command with a path
/// holding spaces can be pasted as it is.
pub fn shell_quote(path: &Path) -> String {
    let text = path.display().to_string();
    let plain = !text.is_empty()
        && text.chars().all(|c| c.is_ascii_alphanumeric() || "/._-+,:=@%".contains(c));
    if plain { text } else { format!("'{}'", text.replace('\'', r"'\''")) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_is_singular() {
        assert_eq!(count(1, "generation", "generations"), "1 generation");
        assert_eq!(count(0, "design", "designs"), "0 designs");
        assert_eq!(count(24, "design", "designs"), "24 designs");
    }

    #[test]
    fn paths_with_spaces_are_quoted() {
        assert_eq!(shell_quote(Path::new("out/front-01.toml")), "out/front-01.toml");
        assert_eq!(shell_quote(Path::new("my runs/a.toml")), "'my runs/a.toml'");
        assert_eq!(shell_quote(Path::new("it's")), r"'it'\''s'");
        assert_eq!(shell_quote(Path::new("")), "''");
    }
}
