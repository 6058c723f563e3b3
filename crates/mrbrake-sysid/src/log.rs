//! Reading test-rig logs: CSV with a header row, columns chosen by name, any sample rate.
//!
//! A log is valid when every requested cell is a finite number and the time column strictly increases;
//! anything else is an error naming the file, the line (the header is line 1) and the column. Lines
//! starting with `#` are comments; cells may carry surrounding spaces.

use std::io::Read;
use std::path::{Path, PathBuf};

use crate::SysidError;

/// Time-stamped channels read from one log file.
#[derive(Debug, Clone)]
pub struct Log {
    /// Where the data came from (for error messages).
    pub source: PathBuf,
    /// Sample times in seconds, strictly increasing.
    pub time_s: Vec<f64>,
    /// The requested channels, in the order they were asked for, each as long as `time_s`.
    pub channels: Vec<Vec<f64>>,
}

impl Log {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// True when the log holds no sample.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Mean sample rate in Hz, (n − 1)/(t_last − t_first).
    pub fn mean_sample_rate_hz(&self) -> f64 {
        mean_sample_rate_hz(&self.time_s)
    }
}

/// Mean sample rate in Hz of the sample times `time_s`, (n − 1)/(t_last − t_first); 0 for fewer
/// than two samples.
pub fn mean_sample_rate_hz(time_s: &[f64]) -> f64 {
    let n = time_s.len();
    if n < 2 {
        return 0.0;
    }
    (n - 1) as f64 / (time_s[n - 1] - time_s[0])
}

/// Checks columns given in memory (a Python caller's arrays) as [`read_log`] checks a file's: every
/// channel as long as the time column, every value finite, time strictly increasing, at least
/// `min_samples` samples. `source` names the data in messages; nothing is copied.
pub fn check_columns(
    source: &Path,
    time: (&str, &[f64]),
    channels: &[(&str, &[f64])],
    min_samples: usize,
) -> Result<(), SysidError> {
    let file_err =
        |message: String| SysidError::File { file: source.to_path_buf(), line: None, message };
    for (name, values) in std::iter::once(&time).chain(channels) {
        if values.len() != time.1.len() {
            return Err(file_err(format!(
                "column '{name}' has {} samples, column '{}' {}",
                values.len(),
                time.0,
                time.1.len()
            )));
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(file_err(format!(
                "column '{name}': {} at index {i} is not a finite number",
                values[i]
            )));
        }
    }
    if let Some(i) = time.1.windows(2).position(|w| w[1] <= w[0]) {
        return Err(file_err(format!(
            "column '{}' must strictly increase: {} at index {} follows {}",
            time.0,
            time.1[i + 1],
            i + 1,
            time.1[i]
        )));
    }
    if time.1.len() < min_samples {
        return Err(file_err(format!(
            "only {} samples; at least {min_samples} are needed",
            time.1.len()
        )));
    }
    Ok(())
}

/// Reads `time_col` and `channel_cols` from the CSV file at `path`; at least `min_samples` rows.
pub fn read_log(
    path: &Path,
    time_col: &str,
    channel_cols: &[&str],
    min_samples: usize,
) -> Result<Log, SysidError> {
    let file = mrbrake_error::read::open(path, mrbrake_error::read::LOG)
        .map_err(|source| SysidError::Io { path: path.to_path_buf(), source })?;
    read_log_from(
        path,
        std::io::BufReader::with_capacity(1 << 16, file),
        time_col,
        channel_cols,
        min_samples,
    )
}

/// As [`read_log`], from any reader; `source` only names the data in error messages.
pub fn read_log_from(
    source: &Path,
    reader: impl Read,
    time_col: &str,
    channel_cols: &[&str],
    min_samples: usize,
) -> Result<Log, SysidError> {
    let mut names = vec![time_col];
    names.extend_from_slice(channel_cols);
    let columns = read_columns_from(source, reader, &names)?;
    let mut columns = columns.into_iter();
    let time_s = columns.next().unwrap_or_default();
    let log = Log { source: source.to_path_buf(), time_s, channels: columns.collect() };
    check_time(&log.source, &log.time_s, time_col)?;
    if log.len() < min_samples {
        return Err(SysidError::File {
            file: log.source,
            line: None,
            message: format!(
                "only {} samples; at least {min_samples} are needed",
                log.time_s.len()
            ),
        });
    }
    Ok(log)
}

/// Reads the named numeric columns (any order in the file) from a CSV source with a header row.
pub fn read_columns_from(
    source: &Path,
    reader: impl Read,
    names: &[&str],
) -> Result<Vec<Vec<f64>>, SysidError> {
    let file_err = file_error(source);
    let mut rdr = csv_reader(reader, true);
    let header = rdr
        .headers()
        .map_err(|e| csv_error(source, Some(1), "cannot read the header row", e))?
        .clone();
    let mut index = Vec::with_capacity(names.len());
    for name in names {
        match header.iter().position(|h| h == *name) {
            Some(i) => index.push(i),
            None => {
                let available: Vec<&str> = header.iter().collect();
                return Err(file_err(
                    Some(1),
                    format!(
                        "no column named '{name}' in the header (columns: {})",
                        available.join(", ")
                    ),
                ));
            }
        }
    }
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut record = csv::StringRecord::new();
    loop {
        match rdr.read_record(&mut record) {
            Ok(false) => break,
            Ok(true) => {}
            Err(e) => return Err(csv_error(source, None, "malformed CSV", e)),
        }
        let line = record.position().map(|p| p.line());
        for (k, &i) in index.iter().enumerate() {
            let cell = record
                .get(i)
                .ok_or_else(|| file_err(line, format!("missing value in column '{}'", names[k])))?;
            let value: f64 = cell.parse().map_err(|_| {
                file_err(line, format!("column '{}': '{cell}' is not a number", names[k]))
            })?;
            if !value.is_finite() {
                return Err(file_err(
                    line,
                    format!("column '{}': {cell} is not a finite number", names[k]),
                ));
            }
            columns[k].push(value);
        }
    }
    Ok(columns)
}

/// Checks that the time column strictly increases; the error names the line of the first violation.
fn check_time(source: &Path, time_s: &[f64], time_col: &str) -> Result<(), SysidError> {
    for i in 1..time_s.len() {
        if time_s[i] <= time_s[i - 1] {
            return Err(SysidError::File {
                file: source.to_path_buf(),
                line: Some(i as u64 + 2),
                message: format!(
                    "column '{time_col}' must strictly increase: {} follows {}",
                    time_s[i],
                    time_s[i - 1]
                ),
            });
        }
    }
    Ok(())
}

/// The CSV reader every sysid file uses: header row, fields trimmed, `#` comment lines skipped;
/// `flexible` allows rows of differing length (logs with trailing annotation columns).
pub(crate) fn csv_reader<R: Read>(reader: R, flexible: bool) -> csv::Reader<R> {
    csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .flexible(flexible)
        .from_reader(reader)
}

/// A constructor of [`SysidError::File`] errors for `file` (line, message).
pub(crate) fn file_error(file: &Path) -> impl Fn(Option<u64>, String) -> SysidError + '_ {
    move |line, message| SysidError::File { file: file.to_path_buf(), line, message }
}

/// A [`SysidError::Csv`] for `file`: the CSV reader's `error` while doing `what`, at `line`, or at
/// the error's own line when `line` is `None`.
pub(crate) fn csv_error(
    file: &Path,
    line: Option<u64>,
    what: &'static str,
    error: csv::Error,
) -> SysidError {
    let line = line.or_else(|| error.position().map(|p| p.line()));
    SysidError::Csv { file: file.to_path_buf(), line, what, source: error }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    fn read(text: &str, min: usize) -> Result<Log, SysidError> {
        read_log_from(
            Path::new("test.csv"),
            text.as_bytes(),
            "time_s",
            &["current_A", "torque_Nm"],
            min,
        )
    }

    /// Columns in memory are checked as a file's are: lengths, finite values, increasing time,
    /// sample count; every failure is an input error naming the column.
    #[test]
    fn columns_in_memory_are_checked_like_a_file() {
        let check = |t: &[f64], i: &[f64], min| {
            check_columns(Path::new("<arrays>"), ("time", t), &[("current", i)], min)
        };
        assert!(check(&[0.0, 0.1, 0.2], &[0.0, 1.0, 2.0], 3).is_ok());
        for (t, i, min, expected) in [
            (&[0.0, 0.1, 0.2][..], &[0.0, 1.0][..], 1, "column 'current' has 2 samples"),
            (&[0.0, 0.1, 0.2], &[0.0, f64::NAN, 2.0], 1, "column 'current': NaN at index 1"),
            (&[0.0, 0.2, 0.1], &[0.0, 1.0, 2.0], 1, "0.1 at index 2 follows 0.2"),
            (&[0.0, 0.1, 0.2], &[0.0, 1.0, 2.0], 4, "only 3 samples; at least 4"),
        ] {
            let err = check(t, i, min).unwrap_err();
            assert!(err.is_input_error(), "{err}");
            assert!(err.to_string().contains(expected), "{err}");
        }
        assert!((mean_sample_rate_hz(&[0.0, 0.1, 0.2]) - 10.0).abs() < 1e-12);
        assert!(mean_sample_rate_hz(&[1.0]).abs() < 1e-300);
    }

    #[test]
    fn columns_are_found_by_name_in_any_order() {
        let log = read("torque_Nm, time_s ,current_A\n0.1,0.0,0\n0.2,0.001,0.5\n", 2).unwrap();
        assert_eq!(log.channels[0], vec![0.0, 0.5]);
        assert_eq!(log.channels[1], vec![0.1, 0.2]);
        assert!((log.mean_sample_rate_hz() - 1000.0).abs() < 1e-9);
    }

    #[test]
    fn nan_is_rejected_with_file_and_line() {
        let err =
            read("time_s,current_A,torque_Nm\n0,0,0\n0.001,NaN,0\n", 1).unwrap_err().to_string();
        assert!(
            err.contains("test.csv") && err.contains("line 3") && err.contains("current_A"),
            "{err}"
        );
    }

    #[test]
    fn non_monotone_time_is_rejected_with_line() {
        let err = read("time_s,current_A,torque_Nm\n0,0,0\n0.002,0,0\n0.001,0,0\n", 1)
            .unwrap_err()
            .to_string();
        assert!(err.contains("line 4") && err.contains("strictly increase"), "{err}");
    }

    #[test]
    fn missing_column_and_missing_value_are_named() {
        let err = read("time_s,current_A\n0,0\n", 1).unwrap_err().to_string();
        assert!(err.contains("torque_Nm") && err.contains("line 1"), "{err}");
        let err = read("time_s,current_A,torque_Nm\n0,0,0\n0.001,0\n", 1).unwrap_err().to_string();
        assert!(err.contains("line 3") && err.contains("torque_Nm"), "{err}");
    }

    #[test]
    fn too_few_samples_is_an_input_error() {
        let err = read("time_s,current_A,torque_Nm\n0,0,0\n", 10).unwrap_err();
        assert!(err.is_input_error());
        assert!(err.to_string().contains("at least 10"));
    }
}
