//! What a program asks the page to show (`POST /api/view`, `GET /api/view`):
//! one configuration or one trajectory of a robot, numbered so that the page
//! applies each request once.

use std::sync::{Arc, Mutex, PoisonError};

use kinema::Robot;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::error::{Error, Result};

/// The body of `POST /api/view`: `q` one configuration, or with `t` one row per sample.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ViewReq {
    pub(crate) robot: Option<String>,
    pub(crate) q: Value,
    pub(crate) t: Option<Vec<f64>>,
}

/// The shape of `ViewReq`, for error messages.
pub(crate) const VIEW_SHAPE: &str =
    r#"{"robot": "NAME", "q": [joint values]} or {"robot": "NAME", "t": [s], "q": [[joint values] per sample]}"#;

/// What the page shows: `q` alone, or a trajectory `t` [s] with one `q` row per sample.
#[derive(Serialize, Clone)]
struct Shown {
    version: u64,
    robot: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    t: Option<Vec<f64>>,
    q: Value,
}

/// The latest request of a program to the page, shared by every clone of the app.
#[derive(Debug, Default, Clone)]
pub(crate) struct ViewSlot(Arc<Mutex<(u64, Option<Value>)>>);

impl ViewSlot {
    /// `{"version": 0}` until a program asked for something, then the latest request with its number.
    pub(crate) fn get(&self) -> Value {
        let slot = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        slot.1.clone().unwrap_or_else(|| serde_json::json!({ "version": 0 }))
    }

    /// Checks `req` against `robot` and makes it the page's next request; answers it with its number.
    pub(crate) fn set(&self, robot: &Robot, req: ViewReq) -> Result<Value> {
        let (t, q) = checked(robot, req)?;
        let mut slot = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        slot.0 += 1;
        let shown = Shown { version: slot.0, robot: robot.name().to_string(), t, q };
        let value = serde_json::to_value(shown).map_err(|e| Error::Internal { message: e.to_string() })?;
        slot.1 = Some(value.clone());
        Ok(value)
    }
}

/// The request's times and configurations, each configuration checked by the core.
fn checked(robot: &Robot, req: ViewReq) -> Result<(Option<Vec<f64>>, Value)> {
    let rows: Vec<Vec<f64>> = match &req.t {
        None => vec![serde_json::from_value(req.q.clone()).map_err(|_| not_shaped("`q` must be a list of numbers"))?],
        Some(_) => serde_json::from_value(req.q.clone())
            .map_err(|_| not_shaped("with `t`, `q` must be a list of rows of numbers"))?,
    };
    for q in &rows {
        robot.check_q(q)?;
    }
    if let Some(t) = &req.t {
        if t.len() != rows.len() || t.len() < 2 {
            return Err(not_shaped(&format!(
                "a trajectory needs two or more samples and one `q` row per time; got {} times and {} rows",
                t.len(),
                rows.len()
            )));
        }
        if t.iter().any(|x| !x.is_finite()) || t.windows(2).any(|w| w[1] <= w[0]) {
            return Err(not_shaped("`t` must be finite and increasing"));
        }
    }
    Ok((req.t, req.q))
}

fn not_shaped(message: &str) -> Error {
    Error::Unprocessable { message: format!("/api/view: {message}; expected JSON {VIEW_SHAPE}") }
}

#[cfg(test)]
mod tests {
    use crate::App;

    #[test]
    fn a_shown_configuration_is_read_back_with_a_new_version() {
        let app = App::new(None).unwrap();
        assert_eq!(app.api("GET", "/api/view", b"").1["version"], 0);
        let (status, shown) = app.api("POST", "/api/view", br#"{"robot": "puma560", "q": [0.1, 0.2, 0.3, 0, 0, 0]}"#);
        assert_eq!(status, 200, "{shown}");
        let (_, read) = app.api("GET", "/api/view", b"");
        assert_eq!(read, shown);
        assert_eq!(read["version"], 1);
        assert_eq!(read["q"][2], 0.3);
        let body = br#"{"robot": "puma560", "t": [0, 1], "q": [[0, 0, 0, 0, 0, 0], [1, 1, 1, 1, 1, 1]]}"#;
        assert_eq!(app.api("POST", "/api/view", body).0, 200);
        let (_, read) = app.api("GET", "/api/view", b"");
        assert_eq!((read["version"].as_u64(), read["t"][1].as_f64()), (Some(2), Some(1.0)));
    }

    #[test]
    fn bad_requests_are_refused_and_change_nothing() {
        let app = App::new(None).unwrap();
        for body in [
            &br#"{"robot": "puma560", "q": [0, 0]}"#[..],
            br#"{"robot": "puma560", "q": [[0, 0, 0, 0, 0, 0]]}"#,
            br#"{"robot": "puma560", "t": [0], "q": [[0, 0, 0, 0, 0, 0]]}"#,
            br#"{"robot": "puma560", "t": [1, 0], "q": [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0]]}"#,
            br#"{"robot": "puma560", "t": [0, 1], "q": [[0, 0, 0, 0, 0, 0], [0, 0, 0]]}"#,
            br#"{"robot": "nobody", "q": [0]}"#,
        ] {
            let (status, answer) = app.api("POST", "/api/view", body);
            assert!(status == 422 || status == 404 || status == 400, "{status} {answer}");
            assert!(answer["error"].is_string());
        }
        assert_eq!(app.api("GET", "/api/view", b"").1["version"], 0);
    }
}
