//! Reading the plain comma-separated files trackd writes (`tracks.csv`, `gt_tracks.csv`):
//! columns addressed by header name, errors naming file and line.

use std::{
    collections::HashMap,
    path::{Path, PathBuf},
    str::FromStr,
};

use crate::error::EvalError;

/// A CSV text whose header holds a given set of columns.
pub(crate) struct Table<'a> {
    path: &'a Path,
    text: &'a str,
    /// For each requested column, its position in a row.
    positions: Vec<usize>,
    /// Fields a row must have (the header's).
    width: usize,
}

/// One data row.
pub(crate) struct Row<'a> {
    path: &'a Path,
    /// 1-based line number in the file.
    pub line: usize,
    fields: Vec<&'a str>,
    positions: &'a [usize],
    names: &'a [&'a str],
}

impl<'a> Table<'a> {
    /// Reads the header of `text` and locates `columns` in it (any order, extra columns allowed).
    pub fn new(path: &'a Path, text: &'a str, columns: &[&str]) -> Result<Self, EvalError> {
        let header = text.lines().next().unwrap_or("");
        let index: HashMap<&str, usize> = header
            .split(',')
            .enumerate()
            .map(|(i, name)| (name.trim(), i))
            .collect();
        let positions = columns
            .iter()
            .map(|&column| {
                index
                    .get(column)
                    .copied()
                    .ok_or_else(|| EvalError::MissingColumn {
                        path: path.to_path_buf(),
                        column: column.to_string(),
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            path,
            text,
            positions,
            width: header.split(',').count(),
        })
    }

    /// The data rows (blank lines skipped), each with `names` (the columns given to `new`, in
    /// that order) to address its fields.
    pub fn rows<'b>(
        &'b self,
        names: &'b [&'b str],
    ) -> impl Iterator<Item = Result<Row<'b>, EvalError>> + 'b {
        self.text
            .lines()
            .enumerate()
            .skip(1)
            .filter(|(_, line)| !line.trim().is_empty())
            .map(move |(i, line)| {
                let fields: Vec<&str> = line.split(',').map(str::trim).collect();
                if fields.len() != self.width {
                    return Err(EvalError::BadRow {
                        path: self.path.to_path_buf(),
                        line: i + 1,
                        message: format!(
                            "{} fields where the header has {}",
                            fields.len(),
                            self.width
                        ),
                    });
                }
                Ok(Row {
                    path: self.path,
                    line: i + 1,
                    fields,
                    positions: &self.positions,
                    names,
                })
            })
    }
}

impl Row<'_> {
    /// The raw text of requested column `k`.
    pub fn text(&self, k: usize) -> &str {
        self.fields[self.positions[k]]
    }

    /// Requested column `k` parsed as `T`.
    pub fn parse<T: FromStr>(&self, k: usize) -> Result<T, EvalError> {
        self.text(k).parse().map_err(|_| EvalError::BadRow {
            path: self.path.to_path_buf(),
            line: self.line,
            message: format!(
                "column `{}`: cannot parse {:?}",
                self.names[k],
                self.text(k)
            ),
        })
    }

    /// Requested column `k` as a finite number (a non-finite one is [`EvalError::NonFinite`]).
    pub fn finite(&self, k: usize) -> Result<f64, EvalError> {
        let value: f64 = self.parse(k)?;
        if value.is_finite() {
            Ok(value)
        } else {
            Err(EvalError::NonFinite {
                path: self.path.to_path_buf(),
                line: self.line,
                column: self.names[k].to_string(),
            })
        }
    }
}

/// Reads a whole file, naming it in the error.
pub(crate) fn read_text(path: &Path) -> Result<String, EvalError> {
    std::fs::read_to_string(path).map_err(|source| EvalError::Io {
        path: PathBuf::from(path),
        source,
    })
}
