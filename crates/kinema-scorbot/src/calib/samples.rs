//! Measured samples read from CSV files.

use std::path::Path;

use kinema::nalgebra::Vector3;

use crate::csvio;
use crate::error::Result;

use super::Sample;

/// Reads samples: CSV with a header naming columns `c1,c2,c3,c4,c5` (counts)
/// and `x,y,z` (measured tool position, metres), in any order; other columns
/// are ignored; blank lines and `#` lines are skipped. Errors name the file,
/// the line and the offending text.
///
/// # Examples
/// ```
/// let path = std::env::temp_dir().join("kinema-scorbot-doc-samples.csv");
/// std::fs::write(&path, "x,y,z,c1,c2,c3,c4,c5\n0.3,0.01,0.4,100,-2000,500,40,-60\n")?;
/// let s = kinema_scorbot::calib::read_samples_csv(&path)?;
/// assert_eq!(s[0].counts, [100.0, -2000.0, 500.0, 40.0, -60.0]);
/// assert_eq!(s[0].position.z, 0.4);
/// # std::fs::remove_file(&path)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_samples_csv(path: &Path) -> Result<Vec<Sample>> {
    Ok(csvio::read_columns(path, &SAMPLE_COLUMNS, &[])?.iter().map(sample).collect())
}

/// Parses the text of a samples file (see [`read_samples_csv`]); `origin`
/// names it in errors.
pub fn parse_samples_csv(text: &str, origin: &str) -> Result<Vec<Sample>> {
    Ok(csvio::parse_columns(text, origin, &SAMPLE_COLUMNS, &[])?.iter().map(sample).collect())
}

const SAMPLE_COLUMNS: [&str; 8] = ["c1", "c2", "c3", "c4", "c5", "x", "y", "z"];

fn sample(r: &csvio::Row) -> Sample {
    let v = &r.req;
    Sample { counts: [v[0], v[1], v[2], v[3], v[4]], position: Vector3::new(v[5], v[6], v[7]) }
}
