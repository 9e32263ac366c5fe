//! Sensing errors of a scenario: a default and overrides by obstacle id.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::dependability::SensingSpec;

/// Sensing errors: a default for every obstacle and overrides by id.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SensingConfig {
    /// Applies to every obstacle without its own entry (default: exact).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub default: Option<SensingSpec>,
    /// Per obstacle id.
    #[serde(flatten)]
    pub obstacles: BTreeMap<String, SensingSpec>,
}

impl SensingConfig {
    /// The sensing of obstacle `id`.
    #[must_use]
    pub fn for_obstacle(&self, id: &str) -> SensingSpec {
        self.obstacles
            .get(id)
            .copied()
            .or(self.default)
            .unwrap_or_default()
    }
}
