//! Error messages for people: an error chain joined once, and source excerpts kept short.
//!
//! Two things made messages hard to read: a cause whose text its parent already repeats (SQLite's
//! "invalid utf-8 sequence…" printed three times in one line), and a parser echoing a whole input
//! line (a 200 000-character TOML line). [`join_causes`] drops a cause already contained in the
//! message; [`clip_excerpts`] cuts the source lines of a `line | text` excerpt (the format of the
//! TOML parser's errors) to a window of [`EXCERPT_WIDTH`] characters around the caret.

/// Characters of an echoed source line kept in a message.
pub const EXCERPT_WIDTH: usize = 120;

/// The causes of an error, outermost first, joined with `": "`, skipping a cause whose text the
/// message already holds (an error that prints its source and also returns it from `source()`).
pub fn join_causes<I, S>(causes: I) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<str>,
{
    let mut message = String::new();
    for cause in causes {
        let cause = cause.as_ref().trim_end();
        if cause.is_empty() || message.contains(cause) {
            continue;
        }
        if !message.is_empty() {
            message.push_str(": ");
        }
        message.push_str(cause);
    }
    message
}

/// `text` with every excerpt source line (`  12 | the line`) longer than [`EXCERPT_WIDTH`]
/// characters cut to a window around the caret of the line below it (`   |    ^`), with `…` where
/// text was cut; the caret line is shifted to match. Other lines are kept as they are.
pub fn clip_excerpts(text: &str) -> String {
    let lines: Vec<&str> = text.split('\n').collect();
    let mut out: Vec<String> = Vec::with_capacity(lines.len());
    let mut index = 0;
    while index < lines.len() {
        let line = lines[index];
        let Some((gutter, source)) = excerpt_source(line) else {
            out.push(line.to_owned());
            index += 1;
            continue;
        };
        let caret = lines.get(index + 1).and_then(|next| excerpt_caret(next));
        let chars: Vec<char> = source.chars().collect();
        if chars.len() <= EXCERPT_WIDTH {
            out.push(line.to_owned());
            index += 1;
            continue;
        }
        let column = caret.map_or(0, |(_, column, _)| column);
        let start = column.saturating_sub(EXCERPT_WIDTH / 2).min(chars.len() - EXCERPT_WIDTH);
        let end = start + EXCERPT_WIDTH;
        let head = if start > 0 { "…" } else { "" };
        let tail = if end < chars.len() { "…" } else { "" };
        let window: String = chars[start..end].iter().collect();
        out.push(format!("{gutter}{head}{window}{tail}"));
        index += 1;
        if let Some((caret_gutter, column, marks)) = caret {
            let shift = column - start + head.chars().count();
            out.push(format!("{caret_gutter}{}{marks}", " ".repeat(shift)));
            index += 1;
        }
    }
    out.join("\n")
}

/// `(gutter including "| ", source text)` of an excerpt source line `<spaces><digits> | <text>`.
fn excerpt_source(line: &str) -> Option<(&str, &str)> {
    let bar = line.find(" | ")?;
    let number = line[..bar].trim_start();
    if number.is_empty() || !number.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    Some(line.split_at(bar + 3))
}

/// `(gutter including "| ", caret column in characters, the carets and anything after)` of a
/// caret line `<spaces>| <spaces>^^^…`.
fn excerpt_caret(line: &str) -> Option<(&str, usize, &str)> {
    let bar = line.find("| ")?;
    if !line[..bar].trim().is_empty() {
        return None;
    }
    let (gutter, rest) = line.split_at(bar + 2);
    let column = rest.chars().take_while(|c| *c == ' ').count();
    let marks = &rest[column..];
    marks.starts_with('^').then_some((gutter, column, marks))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cause_repeated_by_its_parent_is_printed_once() {
        let causes = [
            "results store s.sqlite: SQLite error: Conversion error: invalid utf-8 sequence of 1 bytes",
            "Conversion error: invalid utf-8 sequence of 1 bytes",
            "invalid utf-8 sequence of 1 bytes",
        ];
        let message = join_causes(causes);
        assert_eq!(message.matches("invalid utf-8").count(), 1, "{message}");
        assert_eq!(
            join_causes(["cannot write 'x'", "No space left"]),
            "cannot write 'x': No space left"
        );
    }

    #[test]
    fn a_huge_echoed_line_is_cut_around_the_caret() {
        let long = "x".repeat(100_000) + "@" + &"y".repeat(100_000);
        let message = format!(
            "p.toml: TOML parse error at line 1, column 100001\n  |\n1 | {long}\n  | {}^\ninvalid key\n",
            " ".repeat(100_000)
        );
        let clipped = clip_excerpts(&message);
        assert!(clipped.len() < 600, "{} bytes", clipped.len());
        let lines: Vec<&str> = clipped.lines().collect();
        assert!(lines[2].starts_with("1 | …x") && lines[2].ends_with("y…"), "{}", lines[2]);
        // The caret still points at the '@'.
        let at = lines[2].chars().position(|c| c == '@').unwrap();
        assert_eq!(lines[3].chars().position(|c| c == '^'), Some(at));
        assert_eq!(lines[4], "invalid key");
    }

    #[test]
    fn short_excerpts_and_other_lines_are_unchanged() {
        let message = "f.toml: TOML parse error at line 3, column 5\n  |\n3 | a = [1, 2\n  |     ^\nexpected ]";
        assert_eq!(clip_excerpts(message), message);
        let prose = "a line | with a bar that is no excerpt ".repeat(10);
        assert_eq!(clip_excerpts(&prose), prose);
    }
}
