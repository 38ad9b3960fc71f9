//! The record of the physical tool position (an emulation of the seed's
//! external camera): samples with noise, appended to a CSV file.

use std::fmt::Write as _;
use std::path::Path;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::error::Error;

use super::motion::{Active, MotionKind};
use super::{Controller, MAX_SAMPLES, MAX_SAMPLES_PER_MOTION};

/// Sampling period of the recorded tool position \[s of nominal time\].
const SAMPLE_PERIOD: f64 = 0.01;

impl Controller {
    /// Records the physical tool position along `a` up to `until` \[s,
    /// simulated offset\], every 10 ms of nominal time (coarser if the motion
    /// would give more than [`MAX_SAMPLES_PER_MOTION`]), and appends the new
    /// rows to the file.
    pub(super) fn sample(&mut self, a: &Active, until: f64) {
        if self.record.is_none() || matches!(a.kind, MotionKind::Gripper { .. }) {
            return;
        }
        if self.samples.len() >= MAX_SAMPLES {
            if !self.record_full {
                self.record_full = true;
                let path = self.record.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
                self.record_error = Some(Error::RecordFull { path, max: MAX_SAMPLES });
            }
            return;
        }
        let nominal = until / self.time_scale;
        let period = SAMPLE_PERIOD.max(nominal / MAX_SAMPLES_PER_MOTION as f64);
        let n = (nominal / period - 1e-9).ceil().max(0.0) as usize;
        let from = self.samples.len();
        for k in 0..=n {
            let tau = (k as f64 * period).min(nominal);
            let counts = a.at(tau * self.time_scale);
            let Ok(q) = self.true_constants.angles(&counts) else { continue };
            let Ok(fk) = self.robot.fk(&q) else { continue };
            let p = fk.world_from_tool.pos;
            let mut s = [p.x, p.y, p.z];
            if self.noise > 0.0 {
                for v in &mut s {
                    *v += self.noise * gaussian(&mut self.noise_rng);
                }
            }
            self.samples.push(s);
        }
        self.append_record(from);
    }

    /// Creates the record file with its header (atomically).
    pub(super) fn write_record(&mut self) {
        let Some(path) = &self.record else { return };
        if let Err(e) = write_atomically(path, b"x,y,z\n") {
            if self.record_error.is_none() {
                self.record_error = Some(Error::Record { path: path.display().to_string(), source: e.into() });
            }
        }
    }

    /// Appends the samples from index `from` on to the record file, in one write.
    fn append_record(&mut self, from: usize) {
        let Some(path) = &self.record else { return };
        let mut text = String::with_capacity(64 * (self.samples.len() - from));
        for s in &self.samples[from..] {
            let _ = writeln!(text, "{},{},{}", s[0], s[1], s[2]);
        }
        let result = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .and_then(|mut f| std::io::Write::write_all(&mut f, text.as_bytes()));
        if let Err(e) = result {
            if self.record_error.is_none() {
                self.record_error = Some(Error::Record { path: path.display().to_string(), source: e.into() });
            }
        }
    }
}

/// Writes a temporary file next to `path` (an unpredictable name, created
/// exclusively, removed on any failure) and renames it over `path`.
fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut tmp = tempfile::Builder::new().prefix(".kinema-record-").suffix(".tmp").tempfile_in(dir)?;
    std::io::Write::write_all(&mut tmp, bytes)?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map(|_| ()).map_err(|e| e.error)
}

/// A standard normal deviate (Box–Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}
