//! Reading small CSV tables with line numbers, so that every error can name the file and the line.
//!
//! A small line-based reader (rather than a CSV library) keeps the physical line numbers exact.
//!
//! Lines starting with `#` are comments and blank lines are skipped. The header is compared without
//! regard to case or surrounding spaces.

use crate::MaterialError;

/// One data row of a CSV table.
#[derive(Debug, Clone)]
pub(crate) struct Row {
    /// 1-based line number in the file.
    pub line: u64,
    /// The fields, trimmed.
    pub fields: Vec<String>,
}

impl Row {
    /// Field `index` parsed as a number; `column` names it in the error message.
    pub fn number(&self, index: usize, column: &str, file: &str) -> Result<f64, MaterialError> {
        let text = self.fields.get(index).map(String::as_str).unwrap_or("");
        text.parse::<f64>().map_err(|_| MaterialError::Parse {
            file: file.to_string(),
            line: self.line,
            message: format!("field `{column}` is `{text}`, which is not a number"),
        })
    }

    /// Field `index` as an optional number: empty means `None`.
    pub fn optional_number(
        &self,
        index: usize,
        column: &str,
        file: &str,
    ) -> Result<Option<f64>, MaterialError> {
        match self.fields.get(index).map(String::as_str) {
            None | Some("") => Ok(None),
            Some(_) => self.number(index, column, file).map(Some),
        }
    }

    /// Field `index` as text (empty if missing).
    pub fn text(&self, index: usize) -> &str {
        self.fields.get(index).map(String::as_str).unwrap_or("")
    }
}

/// Reads `text` (the content of `file`) as CSV whose header must be exactly `header` (case-insensitive)
/// and whose rows must have exactly `header.len()` fields.
pub(crate) fn read_rows(
    text: &str,
    file: &str,
    header: &[&str],
) -> Result<Vec<Row>, MaterialError> {
    let mut rows = Vec::new();
    let mut header_seen = false;
    for (index, raw) in text.lines().enumerate() {
        let line = index as u64 + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let fields = split_fields(trimmed).map_err(|message| MaterialError::Parse {
            file: file.to_string(),
            line,
            message,
        })?;
        if !header_seen {
            let matches = fields.len() == header.len()
                && fields.iter().zip(header).all(|(got, want)| got.eq_ignore_ascii_case(want));
            if !matches {
                return Err(MaterialError::Parse {
                    file: file.to_string(),
                    line,
                    message: format!(
                        "the header must be `{}`, found `{}`",
                        header.join(","),
                        fields.join(",")
                    ),
                });
            }
            header_seen = true;
            continue;
        }
        if fields.len() != header.len() {
            return Err(MaterialError::Parse {
                file: file.to_string(),
                line,
                message: format!(
                    "expected {} fields ({}), found {}",
                    header.len(),
                    header.join(","),
                    fields.len()
                ),
            });
        }
        rows.push(Row { line, fields });
    }
    if !header_seen {
        return Err(MaterialError::Parse {
            file: file.to_string(),
            line: 1,
            message: format!("the file is empty; expected the header `{}`", header.join(",")),
        });
    }
    Ok(rows)
}

/// Splits one CSV line into trimmed fields; a field may be quoted (`"a, b"`, with `""` for a quote).
fn split_fields(line: &str) -> Result<Vec<String>, String> {
    let mut fields = Vec::new();
    let mut current = String::new();
    let mut chars = line.chars().peekable();
    let mut in_quotes = false;
    while let Some(c) = chars.next() {
        match (c, in_quotes) {
            ('"', true) if chars.peek() == Some(&'"') => {
                current.push('"');
                chars.next();
            }
            ('"', true) => in_quotes = false,
            ('"', false) if current.trim().is_empty() => {
                current.clear();
                in_quotes = true;
            }
            (',', false) => fields.push(std::mem::take(&mut current).trim().to_string()),
            (c, _) => current.push(c),
        }
    }
    if in_quotes {
        return Err("a quoted field is not closed".to_string());
    }
    fields.push(current.trim().to_string());
    Ok(fields)
}

/// Reads a two-column numeric table; returns `(line, x, y)` triples.
pub(crate) fn read_xy(
    text: &str,
    file: &str,
    header: [&str; 2],
) -> Result<Vec<(u64, f64, f64)>, MaterialError> {
    read_rows(text, file, &header)?
        .into_iter()
        .map(|row| Ok((row.line, row.number(0, header[0], file)?, row.number(1, header[1], file)?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_with_line_numbers_comments_and_blank_lines() {
        let text = "# a comment\nH_A_per_m,B_T\n0,0\n\n10, 0.5\n";
        let rows = read_xy(text, "f.csv", ["H_A_per_m", "B_T"]).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].0, 3);
        assert_eq!(rows[1].0, 5);
        assert!((rows[1].2 - 0.5).abs() < 1e-15);
    }

    #[test]
    fn wrong_header_names_line_and_expected_header() {
        let err = read_xy("H,B\n0,0\n", "f.csv", ["H_A_per_m", "B_T"]).unwrap_err();
        let msg = err.to_string();
        assert!(msg.starts_with("f.csv:1:"), "{msg}");
        assert!(msg.contains("H_A_per_m,B_T"), "{msg}");
    }

    #[test]
    fn not_a_number_and_field_count_name_the_line() {
        let err =
            read_xy("H_A_per_m,B_T\n0,0\n5,abc\n", "f.csv", ["H_A_per_m", "B_T"]).unwrap_err();
        assert!(err.to_string().starts_with("f.csv:3:"), "{err}");
        assert!(err.to_string().contains("B_T"), "{err}");
        let err = read_xy("H_A_per_m,B_T\n0,0,1\n", "f.csv", ["H_A_per_m", "B_T"]).unwrap_err();
        assert!(err.to_string().starts_with("f.csv:2: expected 2 fields"), "{err}");
        let err = read_xy("", "f.csv", ["H_A_per_m", "B_T"]).unwrap_err();
        assert!(err.to_string().contains("empty"), "{err}");
        let err = read_xy("H_A_per_m,B_T\n\"0,0\n", "f.csv", ["H_A_per_m", "B_T"]).unwrap_err();
        assert!(err.to_string().contains("not closed"), "{err}");
    }

    #[test]
    fn quoted_fields_keep_commas() {
        assert_eq!(
            split_fields(r#""Aluminum, 6061-T6",1.0, 2.459e+07"#).unwrap(),
            ["Aluminum, 6061-T6", "1.0", "2.459e+07"]
        );
        assert_eq!(split_fields(r#""say ""hi""",x"#).unwrap(), [r#"say "hi""#, "x"]);
    }
}
