//! Benchmark result tables: printed aligned for people, written as JSON for machines
//! (one object per row, keys = column names with units in the key).

use std::fmt::Write as _;
use std::path::Path;

/// One cell of a benchmark table.
#[derive(Clone, Debug)]
pub enum Cell {
    /// Text (mesh name, adapter, ...).
    Text(String),
    /// An integer count.
    Int(i64),
    /// A measured value, printed with `digits` decimals.
    Num(f64, usize),
    /// A yes/no mark (JSON `true` / `false`; printed `yes` or blank).
    Bool(bool),
    /// No value (written as JSON `null`).
    Empty,
}

impl Cell {
    fn display(&self) -> String {
        match self {
            Cell::Text(s) => s.clone(),
            Cell::Int(i) => i.to_string(),
            Cell::Num(v, d) if v.is_finite() => format!("{v:.d$}", d = *d),
            Cell::Num(..) | Cell::Empty => "-".to_string(),
            Cell::Bool(b) => if *b { "yes" } else { "" }.to_string(),
        }
    }

    fn json(&self) -> String {
        match self {
            Cell::Text(s) => json_string(s),
            Cell::Int(i) => i.to_string(),
            Cell::Num(v, _) if v.is_finite() => format!("{v}"),
            Cell::Num(..) | Cell::Empty => "null".to_string(),
            Cell::Bool(b) => b.to_string(),
        }
    }
}

impl From<&str> for Cell {
    fn from(s: &str) -> Self {
        Cell::Text(s.to_string())
    }
}
impl From<String> for Cell {
    fn from(s: String) -> Self {
        Cell::Text(s)
    }
}
impl From<usize> for Cell {
    fn from(v: usize) -> Self {
        Cell::Int(v as i64)
    }
}
impl From<u32> for Cell {
    fn from(v: u32) -> Self {
        Cell::Int(i64::from(v))
    }
}

fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A benchmark table: column names (with units, e.g. `setup_us_median`) and rows.
#[derive(Clone, Debug, Default)]
pub struct Table {
    /// Title printed above the table.
    pub title: String,
    /// Column names; also the JSON keys.
    pub columns: Vec<String>,
    /// Rows, each as long as `columns`.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// A table with a title and column names.
    pub fn new(title: &str, columns: &[&str]) -> Self {
        Self {
            title: title.to_string(),
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends one row; it must have one cell per column.
    pub fn push(&mut self, row: Vec<Cell>) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "row width must match the columns"
        );
        self.rows.push(row);
    }

    /// The table as aligned text (a markdown table).
    pub fn render(&self) -> String {
        let cells: Vec<Vec<String>> = self
            .rows
            .iter()
            .map(|r| r.iter().map(Cell::display).collect())
            .collect();
        let widths: Vec<usize> = (0..self.columns.len())
            .map(|c| {
                cells
                    .iter()
                    .map(|r| r[c].len())
                    .chain(std::iter::once(self.columns[c].len()))
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        let line = |vals: &[String]| {
            let mut s = String::from("|");
            for (v, w) in vals.iter().zip(&widths) {
                let _ = write!(s, " {v:>w$} |");
            }
            s
        };
        let mut out = format!("## {}\n", self.title);
        out.push_str(&line(&self.columns));
        out.push('\n');
        out.push_str(&line(
            &widths.iter().map(|w| "-".repeat(*w)).collect::<Vec<_>>(),
        ));
        out.push('\n');
        for r in &cells {
            out.push_str(&line(r));
            out.push('\n');
        }
        out
    }

    /// The rows as JSON objects (keys = column names).
    pub fn json_rows(&self) -> Vec<String> {
        self.rows
            .iter()
            .map(|r| {
                let fields: Vec<String> = self
                    .columns
                    .iter()
                    .zip(r)
                    .map(|(k, v)| format!("{}: {}", json_string(k), v.json()))
                    .collect();
                format!("{{{}}}", fields.join(", "))
            })
            .collect()
    }
}

/// Prints every table and, if `json` is given, writes all their rows to it as one JSON
/// array (each row also carries a `table` key naming its table).
pub fn emit(tables: &[Table], json: Option<&Path>) -> anyhow::Result<()> {
    for t in tables {
        println!("{}", t.render());
    }
    if let Some(path) = json {
        let mut rows = Vec::new();
        for t in tables {
            for r in t.json_rows() {
                rows.push(format!(
                    "{{\"table\": {}, {}",
                    json_string(&t.title),
                    &r[1..]
                ));
            }
        }
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(path, format!("[\n  {}\n]\n", rows.join(",\n  ")))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_rows_use_column_names_and_null_for_missing() {
        let mut t = Table::new("t", &["mesh", "time_ms", "count"]);
        t.push(vec!["a\"b".into(), Cell::Num(1.5, 2), 3usize.into()]);
        t.push(vec!["c".into(), Cell::Num(f64::NAN, 2), Cell::Empty]);
        let rows = t.json_rows();
        assert_eq!(rows[0], r#"{"mesh": "a\"b", "time_ms": 1.5, "count": 3}"#);
        assert_eq!(rows[1], r#"{"mesh": "c", "time_ms": null, "count": null}"#);
        let text = t.render();
        assert!(text.contains("|    1.50 |"), "{text}");
        assert!(text.contains("|       - |"), "{text}");
    }
}
