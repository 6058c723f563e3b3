//! The assumptions written in a spec file: its leading comment block (where a spec states what it
//! takes from its source and what it assumes) and every `key = value` line with the comment beside
//! it, in file order, under its `[table]`. The file is read line by line, as written, so nothing a
//! researcher noted is lost or reworded.

/// One `key = value  # comment` line of a spec file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SpecLine {
    /// 1-based line number.
    pub line: usize,
    /// The dotted key (`drum.r0`; top-level keys bare).
    pub key: String,
    /// The value as written.
    pub value: String,
    /// The comment beside it (empty when there is none).
    pub comment: String,
}

/// A spec file's notes.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SpecNotes {
    /// The comment lines before the first key or table, without their `#`.
    pub header: Vec<String>,
    /// Every key line.
    pub lines: Vec<SpecLine>,
}

/// Splits `line` at the first `#` outside a quoted string.
fn split_comment(line: &str) -> (&str, &str) {
    let mut quote: Option<char> = None;
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '#') => return (&line[..i], line[i + 1..].trim()),
            _ => {}
        }
    }
    (line, "")
}

/// The notes of spec text `toml`.
pub fn notes(toml: &str) -> SpecNotes {
    let mut out = SpecNotes::default();
    let mut table = String::new();
    let mut in_header = true;
    for (k, raw) in toml.lines().enumerate() {
        let trimmed = raw.trim();
        if in_header {
            if let Some(comment) = trimmed.strip_prefix('#') {
                out.header
                    .push(comment.strip_prefix(' ').unwrap_or(comment).trim_end().to_string());
                continue;
            }
            if !trimmed.is_empty() {
                in_header = false;
            }
        }
        let (code, comment) = split_comment(trimmed);
        let code = code.trim();
        if let Some(name) = code.strip_prefix('[').and_then(|c| c.strip_suffix(']')) {
            table = name.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        } else if let Some((key, value)) = code.split_once('=') {
            let key = key.trim().trim_matches('"');
            let key = if table.is_empty() { key.to_string() } else { format!("{table}.{key}") };
            out.lines.push(SpecLine {
                line: k + 1,
                key,
                value: value.trim().to_string(),
                comment: comment.to_string(),
            });
        }
    }
    while out.header.last().is_some_and(|l| l.is_empty()) {
        out.header.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_keys_values_and_comments() {
        let text = "# Title\n#\n#   A1. an assumption\n\nname = \"a # b\"  # the name\n[drum]\n\
                    r0 = \"25mm\" # 4.4.2\ngap = 0.0005\n[coil]\nwire = { diameter = \"0.5mm\" }  # Table 5.1\n";
        let n = notes(text);
        assert_eq!(n.header, ["Title", "", "  A1. an assumption"]);
        let keys: Vec<(&str, &str, &str)> = n
            .lines
            .iter()
            .map(|l| (l.key.as_str(), l.value.as_str(), l.comment.as_str()))
            .collect();
        assert_eq!(
            keys,
            [
                ("name", "\"a # b\"", "the name"),
                ("drum.r0", "\"25mm\"", "4.4.2"),
                ("drum.gap", "0.0005", ""),
                ("coil.wire", "{ diameter = \"0.5mm\" }", "Table 5.1"),
            ]
        );
        assert_eq!(n.lines[1].line, 7);
    }
}
