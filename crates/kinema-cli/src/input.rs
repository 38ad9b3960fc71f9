//! Reading input files with a size limit, and the header rule of CSV files.
//!
//! Every file the command reads goes through [`read_limited`], so that a
//! huge file, a FIFO or `/dev/zero` given by mistake is refused with the
//! limit named instead of filling the memory. Robot descriptions are read by
//! the core (`kinema::MAX_DESCRIPTION_BYTES`), which has the same kind of limit.

use std::io::Read;
use std::path::Path;

use anyhow::{bail, Context, Result};

/// The largest CSV input (configurations, targets, trajectories, paths,
/// samples) [bytes]: 64 MiB, about two million 7-joint configurations.
pub(crate) const MAX_CSV_BYTES: u64 = 64 << 20;

/// The largest robot program or constants file [bytes]: 16 MiB.
pub(crate) const MAX_TEXT_BYTES: u64 = 16 << 20;

/// A size in bytes as people read it: "64 MiB" when whole, else bytes.
pub(crate) fn size_text(bytes: u64) -> String {
    if bytes >= 1 << 20 && bytes % (1 << 20) == 0 {
        format!("{} MiB", bytes >> 20)
    } else {
        format!("{bytes} bytes")
    }
}

/// The bytes of `path` (`what` names it in errors, e.g. "CSV input"); an
/// error when it holds more than `max` bytes, found after reading at most
/// `max + 1` of them.
pub(crate) fn read_limited(path: &Path, max: u64, what: &str) -> Result<Vec<u8>> {
    let file = std::fs::File::open(path).with_context(|| format!("cannot read {what} `{}`", path.display()))?;
    let too_big = || anyhow::anyhow!("{what} `{}` is larger than the limit of {}", path.display(), size_text(max));
    if let Ok(m) = file.metadata() {
        if m.is_dir() {
            bail!("cannot read {what} `{}`: it is a folder", path.display());
        }
        if m.is_file() && m.len() > max {
            return Err(too_big());
        }
    }
    let mut bytes = Vec::new();
    file.take(max + 1).read_to_end(&mut bytes).with_context(|| format!("cannot read {what} `{}`", path.display()))?;
    if bytes.len() as u64 > max {
        return Err(too_big());
    }
    Ok(bytes)
}

/// [`read_limited`] for text: an error naming the first byte that is not UTF-8.
pub(crate) fn read_text_limited(path: &Path, max: u64, what: &str) -> Result<String> {
    let bytes = read_limited(path, max, what)?;
    String::from_utf8(bytes).map_err(|e| {
        anyhow::anyhow!("{what} `{}` is not UTF-8 text (byte {})", path.display(), e.utf8_error().valid_up_to())
    })
}

pub(crate) use kinema_io::trajectory_csv::{FirstRow, LineCounter};

/// Classifies a first row as [`FirstRow::of`]; a row that mixes numbers and
/// names (`0,0,0,zz`) is an error naming `line`, as it is a data row with a
/// typo as often as a header.
pub(crate) fn first_row<'a>(fields: impl IntoIterator<Item = &'a str>, path: &Path, line: u64) -> Result<FirstRow> {
    let fields: Vec<&str> = fields.into_iter().collect();
    let row = FirstRow::of(fields.iter().copied());
    if row == FirstRow::Mixed {
        bail!(
            "`{}` line {line}: `{}` mixes numbers and names; a header line has names only, a data line numbers only",
            path.display(),
            fields.join(",")
        )
    }
    Ok(row)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_rows_are_numbers_names_or_an_error() {
        let p = Path::new("q.csv");
        assert_eq!(first_row(["0", " 1.5", "-2e3"], p, 1).unwrap(), FirstRow::Numbers);
        assert_eq!(first_row(["q1", "q2", ""], p, 1).unwrap(), FirstRow::Header);
        let e = first_row(["0", "0", "zz"], p, 3).unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("0,0,zz"), "{e}");
    }

    #[test]
    fn lines_count_from_one_at_byte_offsets() {
        let mut c = LineCounter::new(b"# c\n1,2\n\n# d\n3,4\n");
        assert_eq!(c.line_at(0), 2);
        assert_eq!(c.line_at(8), 5);
        let mut c = LineCounter::new(b"1,2\n3,4");
        assert_eq!((c.line_at(0), c.line_at(4)), (1, 2));
    }

    #[test]
    fn sizes_read_as_mebibytes_when_whole() {
        assert_eq!(size_text(64 << 20), "64 MiB");
        assert_eq!(size_text(1000), "1000 bytes");
    }

    #[test]
    fn reading_stops_after_the_limit() {
        let e = read_limited(Path::new("/dev/zero"), 1000, "CSV input").unwrap_err().to_string();
        assert!(e.contains("larger than the limit of 1000 bytes"), "{e}");
        let dir = std::env::temp_dir().join(format!("kinema-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("small.csv");
        std::fs::write(&f, "1,2\n").unwrap();
        assert_eq!(read_limited(&f, 4, "CSV input").unwrap(), b"1,2\n");
        assert!(read_limited(&f, 3, "CSV input").is_err());
        assert!(read_text_limited(&dir, 3, "program").unwrap_err().to_string().contains("folder"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
