//! The joint trajectory CSV, read and written in one place for every door.
//!
//! Written: a header `t, q1..qn, qd1..qdn, qdd1..qddn`, the tool pose
//! (`x,y,z` and `roll,pitch,yaw` or `rx,ry,rz`) and `manipulability`, then
//! one row per sample. Read: a header naming `t` and `q1..qn` (`qd*`, `qdd*`
//! optional, other columns ignored, any order), cells trimmed, blank and `#`
//! lines skipped. Errors name the file, the line and the column and say what
//! was expected.

use std::fmt;

use kinema::analysis::{yoshikawa, Axes};
use kinema::nalgebra::Matrix6xX;
use kinema::traj::JointTrajectory;
use kinema::{Frame, Robot, RpyConvention};

/// A trajectory CSV that could not be read or written: where, and what was
/// expected there.
#[derive(Debug)]
pub struct CsvError {
    /// The file (or other origin) the text comes from.
    pub origin: String,
    /// The 1-based line the error is on, when it is on one.
    pub line: Option<u64>,
    /// The 1-based column number and the header's name for it, when the
    /// error is in one cell.
    pub column: Option<(usize, String)>,
    /// What is wrong and what was expected.
    pub message: String,
    source: Option<Box<dyn std::error::Error + Send + Sync + 'static>>,
}

impl CsvError {
    fn new(origin: &str, line: Option<u64>, message: String) -> Self {
        CsvError { origin: origin.to_string(), line, column: None, message, source: None }
    }
}

impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}`", self.origin)?;
        if let Some(line) = self.line {
            write!(f, " line {line}")?;
        }
        if let Some((k, name)) = &self.column {
            write!(f, ", column {k} `{name}`")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for CsvError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.source.as_deref().map(|e| e as &(dyn std::error::Error + 'static))
    }
}

/// How the writer prints numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Digits {
    /// A fixed count of decimals (the reader takes half the last one as the
    /// file's resolution).
    Fixed(usize),
    /// The shortest text that reads back to the same `f64`.
    RoundTrip,
}

impl Digits {
    fn format(self, v: f64) -> String {
        match self {
            Digits::Fixed(d) => format!("{v:.d$}"),
            Digits::RoundTrip => format!("{v}"),
        }
    }
}

/// The header [`write_trajectory_csv`] writes for a robot with `n` joints.
pub fn trajectory_header(n: usize, conv: RpyConvention) -> Vec<String> {
    let mut h = vec!["t".to_string()];
    for prefix in ["q", "qd", "qdd"] {
        h.extend((1..=n).map(|i| format!("{prefix}{i}")));
    }
    let rpy = match conv {
        RpyConvention::Zyx => ["roll", "pitch", "yaw"],
        RpyConvention::Xyz => ["rx", "ry", "rz"],
    };
    h.extend(["x", "y", "z"].iter().chain(&rpy).map(|s| s.to_string()));
    h.push("manipulability".into());
    h
}

/// Hands `each` one row per sample: t, q, q̇, q̈, the tool pose and the
/// translational manipulability (Yoshikawa on the linear-velocity rows).
/// Rows are computed one at a time, never held together: a trajectory at the
/// sample limit would need gigabytes as a table.
pub fn for_each_trajectory_row<E: From<kinema::Error>>(
    robot: &Robot,
    traj: &JointTrajectory,
    conv: RpyConvention,
    mut each: impl FnMut(&[f64]) -> Result<(), E>,
) -> Result<(), E> {
    let mut jac = Matrix6xX::zeros(robot.dof());
    let mut row = Vec::with_capacity(1 + 3 * robot.dof() + 7);
    for k in 0..traj.len() {
        let q = traj.q(k);
        let fk = kinema::kin::jacobian_into(robot, q, Frame::Base, &mut jac)?;
        row.clear();
        row.push(traj.times()[k]);
        row.extend_from_slice(q);
        row.extend_from_slice(traj.qd(k));
        row.extend_from_slice(traj.qdd(k));
        let p = fk.world_from_tool;
        row.extend([p.pos.x, p.pos.y, p.pos.z]);
        row.extend(p.rpy(conv));
        row.push(yoshikawa(&jac, Axes::Translation)?);
        each(&row)?;
    }
    Ok(())
}

/// Writes the CSV of a trajectory ([`trajectory_header`], then one row per
/// sample); `origin` names the destination in errors.
pub fn write_trajectory_csv(
    w: impl std::io::Write,
    origin: &str,
    robot: &Robot,
    traj: &JointTrajectory,
    conv: RpyConvention,
    digits: Digits,
) -> Result<(), CsvError> {
    let failed = |e: Box<dyn std::error::Error + Send + Sync>| CsvError {
        source: Some(e),
        ..CsvError::new(origin, None, "cannot be written".into())
    };
    let mut w = csv::Writer::from_writer(w);
    w.write_record(trajectory_header(robot.dof(), conv)).map_err(|e| failed(Box::new(e)))?;
    let mut written = 0u64;
    for_each_trajectory_row(robot, traj, conv, |row| {
        w.write_record(row.iter().map(|&v| digits.format(v))).map_err(|e| WriteError::Csv(failed(Box::new(e))))?;
        written += 1;
        Ok(())
    })
    .map_err(|e| match e {
        WriteError::Csv(e) => e,
        // The row that could not be computed would have been on the line after the last written.
        WriteError::Kinema(e) => {
            CsvError { source: Some(Box::new(e.clone())), ..CsvError::new(origin, Some(written + 2), e.to_string()) }
        }
    })?;
    w.flush().map_err(|e| failed(Box::new(e)))
}

/// Why a row was not written: the file, or the robot's kinematics at a sample.
enum WriteError {
    Csv(CsvError),
    Kinema(kinema::Error),
}

impl From<kinema::Error> for WriteError {
    fn from(e: kinema::Error) -> Self {
        WriteError::Kinema(e)
    }
}

/// A trajectory CSV as read: the trajectory and what the file itself gave.
#[derive(Debug)]
pub struct TrajectoryCsv {
    /// t, q and q̇, q̈ (estimated from q where the file has no such columns).
    pub traj: JointTrajectory,
    /// How finely the file gives (values, times): half the last printed
    /// digit, 0 for numbers with an exponent.
    pub resolution: (f64, f64),
    /// Whether the file has qd1..qdn and qdd1..qddn columns.
    pub given: (bool, bool),
    /// The line of the file each sample comes from.
    pub lines: Vec<u64>,
}

/// Half the last digit of numbers written with a fixed count of decimals:
/// the most decimals seen (a writer of shortest round-trip numbers shows ~17,
/// so its values count as exact); 0 when every number has an exponent.
#[derive(Default)]
struct Decimals(Option<usize>);

impl Decimals {
    fn see(&mut self, text: &str) {
        if text.contains(['e', 'E']) {
            return;
        }
        let d = text.split_once('.').map_or(0, |(_, frac)| frac.len());
        self.0 = Some(self.0.map_or(d, |m| m.max(d)));
    }

    fn resolution(&self) -> f64 {
        self.0.map_or(0.0, |d| 0.5 * 10f64.powi(-(d.min(300) as i32)))
    }
}

/// What the first row of a CSV file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FirstRow {
    /// Every field is a number.
    Numbers,
    /// No field is a number: column names.
    Header,
    /// Some fields are numbers and some are not: a data row with a typo as
    /// often as a header, so neither.
    Mixed,
}

impl FirstRow {
    /// Classifies the fields of a first row.
    pub fn of<'a>(fields: impl IntoIterator<Item = &'a str>) -> FirstRow {
        let (mut numbers, mut all) = (0, 0);
        for f in fields {
            all += 1;
            numbers += usize::from(f.trim().parse::<f64>().is_ok());
        }
        match numbers {
            n if n == all => FirstRow::Numbers,
            0 => FirstRow::Header,
            _ => FirstRow::Mixed,
        }
    }
}

/// Line numbers of CSV records from their byte offsets, met in increasing
/// order: the `csv` crate's position of a record is where its reading began,
/// before the `#` comment and blank lines it skipped, and its line count does
/// not include the comment lines at the start of a file.
pub struct LineCounter<'a> {
    text: &'a [u8],
    byte: usize,
    line: u64,
}

impl<'a> LineCounter<'a> {
    /// A counter over the whole text, at its first line.
    pub fn new(text: &'a [u8]) -> Self {
        LineCounter { text, byte: 0, line: 1 }
    }

    /// The 1-based line of the record read from byte offset `at` on (at or
    /// after the last one asked).
    pub fn line_at(&mut self, at: u64) -> u64 {
        let at = (at as usize).min(self.text.len()).max(self.byte);
        self.line += self.text[self.byte..at].iter().filter(|&&b| b == b'\n').count() as u64;
        self.byte = at;
        while matches!(self.text.get(self.byte), Some(b'#' | b'\n' | b'\r')) {
            match self.text[self.byte..].iter().position(|&b| b == b'\n') {
                Some(n) => {
                    self.byte += n + 1;
                    self.line += 1;
                }
                None => break,
            }
        }
        self.line
    }
}

/// Reads the trajectory CSV `text` for `robot` (see the module); `origin`
/// names it in errors.
pub fn read_trajectory_csv(text: &[u8], origin: &str, robot: &Robot) -> Result<TrajectoryCsv, CsvError> {
    let unreadable = |e: csv::Error| {
        let line = e.position().map(|p| p.line());
        CsvError { source: Some(Box::new(e)), ..CsvError::new(origin, line, "not readable as CSV".into()) }
    };
    let mut rd =
        csv::ReaderBuilder::new().has_headers(false).trim(csv::Trim::All).comment(Some(b'#')).from_reader(text);
    let mut head = csv::StringRecord::new();
    loop {
        if !rd.read_record(&mut head).map_err(unreadable)? {
            let expected = format!("no CSV header; expected one naming t and q1..q{}", robot.dof());
            return Err(CsvError::new(origin, None, expected));
        }
        if !head.iter().all(str::is_empty) {
            break;
        }
    }
    let mut lines = LineCounter::new(text);
    let head_line = lines.line_at(head.position().map_or(0, |p| p.byte()));
    let head_text = head.iter().collect::<Vec<_>>().join(",");
    match FirstRow::of(head.iter()) {
        FirstRow::Header => {}
        FirstRow::Numbers => {
            let message = format!("`{head_text}` is numbers; the first line must be a header naming the columns");
            return Err(CsvError::new(origin, Some(head_line), message));
        }
        FirstRow::Mixed => {
            let message = format!(
                "`{head_text}` mixes numbers and names; a header line has names only, a data line numbers only"
            );
            return Err(CsvError::new(origin, Some(head_line), message));
        }
    }
    let head: Vec<String> = head.iter().map(str::to_string).collect();
    let n = robot.dof();
    let at_header = |message: String| CsvError::new(origin, Some(head_line), message);
    let col = |name: &str| head.iter().position(|h| h == name);
    let t_col = col("t").ok_or_else(|| at_header("the header has no `t` column".into()))?;
    let cols = |prefix: &str| -> Option<Vec<usize>> { (1..=n).map(|i| col(&format!("{prefix}{i}"))).collect() };
    let q_cols = cols("q").ok_or_else(|| {
        at_header(format!("the header must name q1..q{n} for robot `{}` (it has {head_text})", robot.name()))
    })?;
    if col(&format!("q{}", n + 1)).is_some() {
        return Err(at_header(format!("the file has more joint columns than robot `{}` ({n} joints)", robot.name())));
    }
    let (qd_cols, qdd_cols) = (cols("qd"), cols("qdd"));
    let mut t = Vec::new();
    let mut qs: Vec<f64> = Vec::new();
    let mut qds: Vec<f64> = Vec::new();
    let mut qdds: Vec<f64> = Vec::new();
    let mut sample_lines = Vec::new();
    let (mut value_digits, mut time_digits) = (Decimals::default(), Decimals::default());
    let mut rec = csv::StringRecord::new();
    while rd.read_record(&mut rec).map_err(unreadable)? {
        let line = lines.line_at(rec.position().map_or(0, |p| p.byte()));
        sample_lines.push(line);
        let get = |c: usize, digits: &mut Decimals| -> Result<f64, CsvError> {
            let s = rec.get(c).unwrap_or("");
            digits.see(s);
            s.parse::<f64>().map_err(|_| CsvError {
                column: Some((c + 1, head[c].clone())),
                ..CsvError::new(origin, Some(line), format!("`{s}` is not a number; expected a decimal number"))
            })
        };
        t.push(get(t_col, &mut time_digits)?);
        for &c in &q_cols {
            qs.push(get(c, &mut value_digits)?);
        }
        for (cols, out) in [(&qd_cols, &mut qds), (&qdd_cols, &mut qdds)] {
            for &c in cols.iter().flatten() {
                out.push(get(c, &mut value_digits)?);
            }
        }
    }
    if t.is_empty() {
        return Err(CsvError::new(origin, None, "holds no samples; expected rows of numbers after the header".into()));
    }
    // Velocities and accelerations the file does not give are estimated from the positions.
    let given = (qd_cols.is_some(), qdd_cols.is_some());
    let traj = JointTrajectory::from_samples(n, t, qs, qd_cols.map(|_| qds), qdd_cols.map(|_| qdds))
        .map_err(|e| CsvError { source: Some(Box::new(e.clone())), ..CsvError::new(origin, None, e.to_string()) })?;
    Ok(TrajectoryCsv {
        traj,
        resolution: (value_digits.resolution(), time_digits.resolution()),
        given,
        lines: sample_lines,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded random trajectory on `robot`: increasing times, q, q̇, q̈ in [-1, 1).
    fn random_trajectory(robot: &Robot, seed: u64, samples: usize) -> JointTrajectory {
        // splitmix64: the test needs reproducible numbers, not a random crate.
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            (z ^ (z >> 31)) as f64 / u64::MAX as f64 * 2.0 - 1.0
        };
        let n = robot.dof();
        let t: Vec<f64> = (0..samples).map(|k| k as f64 * 0.01 + 0.004 * (next() + 1.0)).collect();
        let mut values = |len: usize| (0..len).map(|_| next()).collect::<Vec<f64>>();
        let (q, qd, qdd) = (values(samples * n), values(samples * n), values(samples * n));
        JointTrajectory::from_samples(n, t, q, Some(qd), Some(qdd)).unwrap()
    }

    fn read(text: &str) -> Result<TrajectoryCsv, CsvError> {
        read_trajectory_csv(text.as_bytes(), "q.csv", &Robot::builtin("puma560").unwrap())
    }

    #[test]
    fn round_trip_digits_read_back_exactly() {
        let robot = Robot::builtin("puma560").unwrap();
        let traj = random_trajectory(&robot, 36, 50);
        let mut text = Vec::new();
        write_trajectory_csv(&mut text, "out.csv", &robot, &traj, RpyConvention::Zyx, Digits::RoundTrip).unwrap();
        let back = read_trajectory_csv(&text, "out.csv", &robot).unwrap();
        assert_eq!(back.given, (true, true));
        assert_eq!(back.lines, (2..52).collect::<Vec<u64>>());
        assert_eq!(back.traj.len(), traj.len());
        assert_eq!(back.traj.times(), traj.times());
        for k in 0..traj.len() {
            assert_eq!(back.traj.q(k), traj.q(k), "q at sample {k}");
            assert_eq!(back.traj.qd(k), traj.qd(k), "qd at sample {k}");
            assert_eq!(back.traj.qdd(k), traj.qdd(k), "qdd at sample {k}");
        }
    }

    #[test]
    fn fixed_digits_give_the_resolution() {
        let robot = Robot::builtin("puma560").unwrap();
        let traj = random_trajectory(&robot, 7, 5);
        let mut text = Vec::new();
        write_trajectory_csv(&mut text, "out.csv", &robot, &traj, RpyConvention::Xyz, Digits::Fixed(6)).unwrap();
        let head = String::from_utf8(text.clone()).unwrap();
        assert!(head.starts_with("t,q1,q2,q3,q4,q5,q6,qd1,") && head.contains(",rx,ry,rz,manipulability\n"), "{head}");
        let back = read_trajectory_csv(&text, "out.csv", &robot).unwrap();
        assert_eq!(back.resolution, (0.5e-6, 0.5e-6));
        for k in 0..traj.len() {
            for (a, b) in back.traj.q(k).iter().zip(traj.q(k)) {
                assert!((a - b).abs() <= 0.5e-6, "{a} {b}");
            }
        }
    }

    #[test]
    fn comments_and_missing_rates_are_allowed() {
        let s =
            read("# made by hand\n\nt, q1,q2,q3,q4,q5,q6, note\n0,0,0,0,0,0,0,x\n# pause\n1,1,0,0,0,0,0,y\n").unwrap();
        assert_eq!((s.given, s.lines.clone()), ((false, false), vec![4, 6]));
        assert_eq!(s.traj.q(1)[0], 1.0);
    }

    #[test]
    fn bad_inputs_are_errors_naming_the_place() {
        let e = read("").unwrap_err();
        assert_eq!(e.line, None);
        assert!(e.to_string().starts_with("`q.csv`: no CSV header; expected one naming t and q1..q6"), "{e}");

        let e = read("t,q1,q2,q3,q4,q5,q6\n").unwrap_err();
        assert!(e.to_string().contains("`q.csv`: holds no samples"), "{e}");

        let e = read("# c\nt,q1,q2,q3,q4,q5\n0,0,0,0,0,0\n").unwrap_err();
        assert_eq!(e.line, Some(2));
        assert!(e.to_string().contains("must name q1..q6 for robot `puma560` (it has t,q1,q2,q3,q4,q5)"), "{e}");

        let e = read("q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0\n").unwrap_err();
        assert!(e.to_string().contains("no `t` column"), "{e}");

        let e = read("t,q1,q2,q3,q4,q5,q6,q7\n0,0,0,0,0,0,0,0\n").unwrap_err();
        assert!(e.to_string().contains("more joint columns"), "{e}");

        let e = read("t,q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0,0\n# c\n0.1,0,zero,0,0,0,0\n").unwrap_err();
        assert_eq!((e.line, e.column.clone()), (Some(4), Some((3, "q2".to_string()))));
        assert_eq!(e.to_string(), "`q.csv` line 4, column 3 `q2`: `zero` is not a number; expected a decimal number");

        let e = read("t,q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0,0\n0.1,0,0\n").unwrap_err();
        assert!(e.to_string().starts_with("`q.csv` line 3: not readable as CSV"), "{e}");
        assert!(std::error::Error::source(&e).is_some_and(|c| c.to_string().contains("fields")), "{e:?}");

        let e = read("0,0,0,0,0,0,0\n").unwrap_err();
        assert!(e.to_string().contains("line 1: `0,0,0,0,0,0,0` is numbers"), "{e}");
        let e = read("t,q1,0\n").unwrap_err();
        assert!(e.to_string().contains("mixes numbers and names"), "{e}");
    }

    #[test]
    fn first_rows_are_classified() {
        assert_eq!(FirstRow::of(["1", " 2.5 "]), FirstRow::Numbers);
        assert_eq!(FirstRow::of(["t", "q1"]), FirstRow::Header);
        assert_eq!(FirstRow::of(["t", "1"]), FirstRow::Mixed);
    }
}
