//! serde's messages in the project's words: what was expected and what was
//! given, never a Rust type name (`invalid type: integer `5`, expected
//! struct DampingConfig` → `expected an object { epsilon, lambdaMax }, got 5`).

use serde::de::{self, DeserializeOwned, Visitor};

/// Rust integer types that hold no negative value.
const UNSIGNED: &[&str] = &["u8", "u16", "u32", "u64", "usize"];
/// Rust integer types that hold negative values.
const SIGNED: &[&str] = &["i8", "i16", "i32", "i64", "isize"];

/// A serde message in the project's words (see the module docs).
pub fn plain_reason(reason: &str) -> String {
    if let Some(rest) = reason.strip_prefix("data did not match any variant of untagged enum ") {
        return match rest.trim() {
            "RadiusSpec" => {
                "expected a number, [r0, r1] or { d?, a?, extension? } of these".to_owned()
            }
            _ => "not one of the accepted forms of this field".to_owned(),
        };
    }
    for prefix in ["invalid type: ", "invalid value: "] {
        if let Some(rest) = reason.strip_prefix(prefix)
            && let Some((got, expected)) = rest.split_once(", expected ")
        {
            return format!(
                "expected {}, got {}",
                expected_words(expected),
                got_words(got)
            );
        }
    }
    if let Some(rest) = reason.strip_prefix("invalid length ")
        && let Some((n, expected)) = rest.split_once(", expected ")
    {
        // A fixed-size array given too many elements says only "fewer".
        if expected.trim() == "fewer elements in array" {
            return format!("too many elements: got {n}, more than this field holds");
        }
        return format!("expected {}, got {n} elements", expected_words(expected));
    }
    if let Some(rest) = reason.strip_prefix("unknown variant `")
        && let Some((name, known)) = rest.split_once("`, expected ")
    {
        return format!("unknown value \"{name}\" (known: {})", names_list(known));
    }
    if let Some(rest) = reason.strip_prefix("unknown field `")
        && let Some((name, known)) = rest.split_once("`, expected ")
    {
        return format!("unknown field \"{name}\" (known: {})", names_list(known));
    }
    if let Some(rest) = reason.strip_prefix("unknown field `")
        && let Some((name, _)) = rest.split_once("`, there are no fields")
    {
        return format!("unknown field \"{name}\" (this object takes no fields)");
    }
    reason.to_owned()
}

/// `one of `a`, `b`` or `` `a` or `b` `` → `a, b`.
fn names_list(known: &str) -> String {
    known
        .trim_start_matches("one of ")
        .replace("` or `", ", ")
        .replace('`', "")
}

/// What serde says was expected, in words.
fn expected_words(expected: &str) -> String {
    if let Some(name) = expected.strip_prefix("struct ") {
        return match struct_fields(name.trim()) {
            Some(fields) if !fields.is_empty() => format!("an object {{ {} }}", fields.join(", ")),
            _ => "an object".to_owned(),
        };
    }
    if expected.starts_with("internally tagged") || expected.starts_with("adjacently tagged") {
        return "an object { type, … }".to_owned();
    }
    if expected == "string or map" || expected.starts_with("map with a single key") {
        return "a string".to_owned();
    }
    if expected == "f64" || expected == "f32" {
        return "a number".to_owned();
    }
    if UNSIGNED.contains(&expected) {
        return "a whole number ≥ 0".to_owned();
    }
    if SIGNED.contains(&expected) {
        return "a whole number".to_owned();
    }
    if expected.starts_with("a sequence") {
        return "an array".to_owned();
    }
    if expected == "a boolean" || expected == "bool" {
        return "true or false".to_owned();
    }
    expected.to_owned()
}

/// What serde says was given (`integer `5``, `map`, `sequence`), in words.
fn got_words(got: &str) -> String {
    let plain = got.replace('`', "");
    for prefix in ["integer ", "floating point ", "boolean "] {
        if let Some(v) = plain.strip_prefix(prefix) {
            return v.to_owned();
        }
    }
    match plain.as_str() {
        "map" => "an object".to_owned(),
        "sequence" => "an array".to_owned(),
        "unit value" | "Option value" => "null".to_owned(),
        _ => plain
            .strip_prefix("string ")
            .map_or(plain.clone(), |s| format!("the string {s}")),
    }
}

/// Asks a struct for its serde name and field names (see [`fields_of`]).
type StructFields = fn() -> Option<(&'static str, &'static [&'static str])>;

/// The fields of the named struct, among those a caller can pass.
fn struct_fields(name: &str) -> Option<&'static [&'static str]> {
    use crate::avoidance::{Clik2Gains, ControllerConfig, DampingConfig, TorqueGains};
    use crate::kinematics::{BranchSpec, JointSpec, PoseSpec, RobotSpec};
    use crate::scenario::{DhValues, HumanSpec, ObstacleSpec, Scenario, SensingConfig};
    const KNOWN: &[StructFields] = &[
        fields_of::<ControllerConfig>,
        fields_of::<DampingConfig>,
        fields_of::<TorqueGains>,
        fields_of::<Clik2Gains>,
        fields_of::<crate::avoidance::ProtectiveConfig>,
        fields_of::<crate::dependability::DependabilityConfig>,
        fields_of::<crate::dependability::SensingSpec>,
        fields_of::<Scenario>,
        fields_of::<ObstacleSpec>,
        fields_of::<HumanSpec>,
        fields_of::<SensingConfig>,
        fields_of::<DhValues>,
        fields_of::<crate::control_point::DhPoint>,
        fields_of::<PoseSpec>,
        fields_of::<JointSpec>,
        fields_of::<BranchSpec>,
        fields_of::<RobotSpec>,
        fields_of::<crate::parsers::urdf::UrdfOptions>,
    ];
    KNOWN
        .iter()
        .filter_map(|f| f())
        .find(|(n, _)| *n == name)
        .map(|(_, fields)| fields)
}

/// The serde name and field names of struct `T`, asked of its
/// `Deserialize` implementation (it names them when it starts reading).
fn fields_of<T: DeserializeOwned>() -> Option<(&'static str, &'static [&'static str])> {
    match T::deserialize(Introspect) {
        Err(Found::Struct(name, fields)) => Some((name, fields)),
        _ => None,
    }
}

/// A deserializer that reads nothing: it only records the struct asked for.
struct Introspect;

#[derive(Debug)]
enum Found {
    Struct(&'static str, &'static [&'static str]),
    Other,
}

impl std::fmt::Display for Found {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("introspection")
    }
}

impl std::error::Error for Found {}

impl de::Error for Found {
    fn custom<T: std::fmt::Display>(_msg: T) -> Self {
        Self::Other
    }
}

impl<'de> de::Deserializer<'de> for Introspect {
    type Error = Found;

    fn deserialize_any<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, Found> {
        Err(Found::Other)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        _visitor: V,
    ) -> Result<V::Value, Found> {
        Err(Found::Struct(name, fields))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
        bytes byte_buf option unit unit_struct newtype_struct seq tuple
        tuple_struct map enum identifier ignored_any
    }
}

#[cfg(test)]
mod tests {
    use wasm_bindgen_test::wasm_bindgen_test as test;

    use super::plain_reason;

    #[test]
    fn serde_words_become_the_projects() {
        assert_eq!(
            plain_reason("invalid type: integer `5`, expected struct DampingConfig"),
            "expected an object { epsilon, lambdaMax }, got 5"
        );
        assert_eq!(
            plain_reason("invalid type: integer `5`, expected string or map"),
            "expected a string, got 5"
        );
        assert_eq!(
            plain_reason("unknown variant `x`, expected one of `velocity`, `torque`, `clik2`"),
            "unknown value \"x\" (known: velocity, torque, clik2)"
        );
        assert_eq!(
            plain_reason("unknown variant `x`, expected `standard` or `modified`"),
            "unknown value \"x\" (known: standard, modified)"
        );
        assert_eq!(
            plain_reason("invalid value: integer `-1`, expected usize"),
            "expected a whole number ≥ 0, got -1"
        );
        assert_eq!(
            plain_reason("invalid length 4, expected fewer elements in array"),
            "too many elements: got 4, more than this field holds"
        );
        assert_eq!(
            plain_reason("invalid length 2, expected an array of length 3"),
            "expected an array of length 3, got 2 elements"
        );
        assert_eq!(
            plain_reason("invalid type: map, expected a sequence"),
            "expected an array, got an object"
        );
    }
}
