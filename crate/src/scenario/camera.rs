//! How a scenario asks to be looked at: the direction of the 3D view and
//! the points a fit keeps on screen besides the robot.
//!
//! The simulation ignores it; viewers apply it when they load the scenario
//! (the playground and the embedded widget do, `docs/scenarios.md`). A
//! direction and points, not a fixed eye: the viewer still fits the view to
//! whatever size and aspect the page gives it, so an authored view holds on
//! a phone as on a desktop.
//!
//! Why points: a fit frames the robot and the obstacles within its reach
//! when the scenario loads. A person who walks in from afar is out of reach
//! then and would be framed by chance (in `human-panda`, at the edge of the
//! view, right beside the camera). The author names where the interaction
//! will take place and the view keeps it in frame from the start.

use serde::{Deserialize, Serialize};

use crate::distance::domain::MAX_COORDINATE;
use crate::error::{FieldError, bounded, finite};

/// Largest pitch (rad): the view stays this far from looking straight down
/// or up, where its "up" direction would be undefined (the viewer's limit).
pub const MAX_PITCH: f64 = 1.55;

/// Most points a camera may ask to frame.
pub const MAX_FRAME_POINTS: usize = 64;

/// The view a scenario asks for (every field optional).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct CameraSpec {
    /// Azimuth of the eye about the world z axis (rad; 0 puts the eye on
    /// the +x side, π/2 on the +y side; viewer default −0.6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw: Option<f64>,
    /// Elevation of the eye above the ground plane (rad, within ±1.55;
    /// viewer default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pitch: Option<f64>,
    /// World points (m) a fit keeps on screen besides the robot and the
    /// obstacles within its reach (at most [`MAX_FRAME_POINTS`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub frame: Vec<[f64; 3]>,
}

impl CameraSpec {
    /// Checks every value.
    ///
    /// # Errors
    /// `yaw: not a finite number`, `pitch: must be within ±1.55 rad (got 2)`,
    /// `frame[1][2]: not a finite number`, `frame: at most 64 points (got 65)`.
    pub fn validate(&self) -> Result<(), FieldError> {
        if let Some(yaw) = self.yaw {
            finite("yaw", yaw)?;
        }
        if let Some(pitch) = self.pitch {
            let pitch = finite("pitch", pitch)?;
            if pitch.abs() > MAX_PITCH {
                return Err(FieldError::new(
                    "pitch",
                    format!("must be within ±{MAX_PITCH} rad (got {pitch})"),
                ));
            }
        }
        if self.frame.len() > MAX_FRAME_POINTS {
            return Err(FieldError::new(
                "frame",
                format!(
                    "at most {MAX_FRAME_POINTS} points (got {})",
                    self.frame.len()
                ),
            ));
        }
        for (k, p) in self.frame.iter().enumerate() {
            for (i, x) in p.iter().enumerate() {
                bounded(&format!("frame[{k}][{i}]"), *x, MAX_COORDINATE)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::*;

    fn parse(json: &str) -> Result<CameraSpec, String> {
        let c: CameraSpec = serde_json::from_str(json).map_err(|e| e.to_string())?;
        c.validate().map_err(|e| e.to_string())?;
        Ok(c)
    }

    #[test]
    fn every_field_is_optional_and_round_trips() {
        assert_eq!(parse("{}").unwrap(), CameraSpec::default());
        let c = parse(r#"{ "yaw": -1.3, "pitch": 0.4, "frame": [[0.8, 0, 1.1]] }"#).unwrap();
        assert_eq!((c.yaw, c.pitch), (Some(-1.3), Some(0.4)));
        assert_eq!(c.frame, vec![[0.8, 0.0, 1.1]]);
        let back: CameraSpec = serde_json::from_value(serde_json::to_value(&c).unwrap()).unwrap();
        assert_eq!(back, c);
        assert_eq!(serde_json::to_string(&CameraSpec::default()).unwrap(), "{}");
    }

    #[test]
    fn bad_values_are_named() {
        let err = |json: &str| parse(json).unwrap_err();
        assert!(err(r#"{ "pitch": 1.6 }"#).starts_with("pitch: must be within ±1.55"));
        assert!(err(r#"{ "pitch": -1.6 }"#).starts_with("pitch: "));
        assert!(err(r#"{ "frame": [[0, 0, 2e6]] }"#).starts_with("frame[0][2]: must be within"));
        assert!(err(r#"{ "zoom": 2 }"#).contains("unknown field `zoom`"));
        let many = format!("{{ \"frame\": [{}] }}", vec!["[0,0,0]"; 65].join(","));
        assert_eq!(err(&many), "frame: at most 64 points (got 65)");
        // NaN cannot be written in JSON; a value built in code is checked too.
        let nan = CameraSpec {
            yaw: Some(f64::NAN),
            ..CameraSpec::default()
        };
        assert_eq!(
            nan.validate().unwrap_err().to_string(),
            "yaw: not a finite number"
        );
        // 1.55 itself is allowed.
        assert!(parse(r#"{ "pitch": 1.55 }"#).is_ok());
    }
}
