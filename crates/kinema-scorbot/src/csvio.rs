//! Reading the crate's CSV inputs: a header line naming the columns, then one
//! row of numbers per line. Blank lines and lines starting with `#` are
//! skipped; columns are found by name in any order; extra columns are ignored.

use std::path::Path;

use crate::error::{Error, Result};

/// One data row: the required columns' values, then the optional ones'.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Row {
    /// Values of the required columns, in the order asked for.
    pub req: Vec<f64>,
    /// Values of the optional columns (None when the file has no such column).
    pub opt: Vec<Option<f64>>,
}

/// Reads `path`; every value of a named column must be a finite number.
/// Errors name the file, the line and the offending text.
pub(crate) fn read_columns(path: &Path, required: &[&str], optional: &[&str]) -> Result<Vec<Row>> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(format!("cannot read `{name}`"), e))?;
    parse_columns(&text, &name, required, optional)
}

/// [`read_columns`] on text; `origin` names it in errors.
pub(crate) fn parse_columns(text: &str, origin: &str, required: &[&str], optional: &[&str]) -> Result<Vec<Row>> {
    let err = |line: usize, message: String| Error::Csv { path: origin.into(), line: Some(line), message };
    let mut lines =
        text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())).filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let Some((hline, header)) = lines.next() else {
        return Err(Error::Csv {
            path: origin.into(),
            line: None,
            message: format!("it is empty; expected a header with columns {}", required.join(",")),
        });
    };
    let names: Vec<String> = header.split(',').map(|s| s.trim().trim_matches('"').to_ascii_lowercase()).collect();
    let find = |c: &str| names.iter().position(|n| n == c);
    let mut req_idx = Vec::with_capacity(required.len());
    for c in required {
        req_idx.push(find(c).ok_or_else(|| {
            err(hline, format!("the header `{header}` has no column `{c}`; required columns: {}", required.join(",")))
        })?);
    }
    let opt_idx: Vec<Option<usize>> = optional.iter().map(|c| find(c)).collect();
    let mut rows = Vec::new();
    for (ln, line) in lines {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let cell = |i: usize, col: &str| -> Result<f64> {
            let Some(t) = cells.get(i) else {
                return Err(err(ln, format!("{} values, but column `{col}` is number {}", cells.len(), i + 1)));
            };
            match t.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(err(ln, format!("column `{col}`: `{t}` is not a finite number"))),
            }
        };
        let req = req_idx.iter().zip(required).map(|(&i, c)| cell(i, c)).collect::<Result<Vec<_>>>()?;
        let opt =
            opt_idx.iter().zip(optional).map(|(i, c)| i.map(|i| cell(i, c)).transpose()).collect::<Result<Vec<_>>>()?;
        rows.push(Row { req, opt });
    }
    if rows.is_empty() {
        return Err(Error::Csv { path: origin.into(), line: None, message: "it has a header but no data rows".into() });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_by_name_with_comments_and_errors_with_lines() {
        let t = "# measured\nz, x ,y,extra\n\n3,1,2,9\n6,4,5,9\n";
        let r = parse_columns(t, "m.csv", &["x", "y", "z"], &["pitch"]).unwrap();
        assert_eq!(r[1].req, [4.0, 5.0, 6.0]);
        assert_eq!(r[0].opt, [None]);
        let e = parse_columns("x,y\n1,2\n", "m.csv", &["x", "y", "z"], &[]).unwrap_err();
        assert!(matches!(&e, Error::Csv { path, line: Some(1), .. } if path == "m.csv"), "{e:?}");
        assert!(e.to_string().starts_with("m.csv:1:") && e.to_string().contains("`z`"), "{e}");
        let e = parse_columns("x,y,z\n1,2,3\n1,nan,3\n", "m.csv", &["x", "y", "z"], &[]).unwrap_err();
        assert!(e.to_string().starts_with("m.csv:3:") && e.to_string().contains("`nan`"), "{e}");
        let e = parse_columns("x,y,z\n1,2\n", "m.csv", &["x", "y", "z"], &[]).unwrap_err();
        assert!(e.to_string().contains("2 values"), "{e}");
        assert!(parse_columns("", "m.csv", &["x"], &[]).is_err());
        let e = parse_columns("x\n", "m.csv", &["x"], &[]).unwrap_err();
        assert!(matches!(&e, Error::Csv { line: None, .. }) && e.to_string().contains("no data rows"), "{e:?}");
    }
}
