//! The example scenarios shipped with the crate (`scenarios/*.json`).

use super::{Scenario, ScenarioError};
use crate::error::FieldError;

/// Names of the example scenarios shipped with the crate.
pub const EXAMPLE_NAMES: [&str; 7] = [
    "planar-transition",
    "lwr4-elbow",
    "human-panda",
    "human-reach",
    "dual-arm-self",
    "chattering",
    "sliding-point",
];

/// The JSON text of example `name`.
///
/// # Errors
/// `name: unknown example "x" (known: …)`.
pub fn example_json(name: &str) -> Result<&'static str, FieldError> {
    Ok(match name {
        "planar-transition" => include_str!("../../../scenarios/planar-transition.json"),
        "lwr4-elbow" => include_str!("../../../scenarios/lwr4-elbow.json"),
        "human-panda" => include_str!("../../../scenarios/human-panda.json"),
        "human-reach" => include_str!("../../../scenarios/human-reach.json"),
        "dual-arm-self" => include_str!("../../../scenarios/dual-arm-self.json"),
        "chattering" => include_str!("../../../scenarios/chattering.json"),
        "sliding-point" => include_str!("../../../scenarios/sliding-point.json"),
        _ => {
            return Err(FieldError::new(
                "name",
                format!(
                    "unknown example \"{name}\" (known: {})",
                    EXAMPLE_NAMES.join(", ")
                ),
            ));
        }
    })
}

/// Example scenario `name`, parsed and validated.
///
/// # Errors
/// An unknown name.
pub fn example(name: &str) -> Result<Scenario, ScenarioError> {
    Scenario::from_json(example_json(name)?)
}
